// Which configuration keys a run resumed from a restart file may change (docs/restart.md). A
// restart file records the configuration it was made with; a key whose value shaped what the
// file already holds (the specimen, the physics of a stage already run) must keep it, or the
// resumed run would mix two experiments in one history. Everything else (output intervals, the
// target strain, the next stage's parameters, threads) may change and is recorded as changed.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <dem/io/config.hpp>

namespace dem::lab {

/// How far the run in a restart file got, in the order a run goes.
enum class RunProgress : int { Generating = 0, Generated, Consolidating, Consolidated, Shearing, Done };

/// "generating", "generated", ...: for messages.
std::string to_string(RunProgress progress);

/// One key's rule: it keeps the file's value once the run has reached `fixed_from`; a
/// reconsolidation (ResumeIntent::Reconsolidate of a consolidated specimen) may change it anyway
/// when `reconsolidation_may_change`. `why` ends the refusal ("the specimen was grown with it").
struct ResumeRule {
  RunProgress fixed_from = RunProgress::Generating;
  bool never_fixed = false;  // may always change (outputs, threads)
  bool reconsolidation_may_change = false;
  std::string why;
};

/// The rule of a key of simple_shear_schema(); std::logic_error for a key it does not know.
ResumeRule resume_rule(const std::string& key);

/// Every key of `config` with its value as text, exact (reals with 17 significant digits).
std::vector<std::pair<std::string, std::string>> configuration_record(const io::Config& config);

/// A key whose value differs between a restart file's record and this run's configuration.
struct ResumeChange {
  std::string key, file_value, new_value;
};

/// Compares a restart file's record with this run's: returns the changes the rules allow, or
/// throws dem::InputError naming every refused key with both values and why (`where` names the
/// file). Keys only one of the records has (another version's schema) are left alone.
std::vector<ResumeChange> check_resume(const std::vector<std::pair<std::string, std::string>>& file_record,
                                       const std::vector<std::pair<std::string, std::string>>& now, RunProgress progress,
                                       bool reconsolidate, const std::string& where);

}  // namespace dem::lab
