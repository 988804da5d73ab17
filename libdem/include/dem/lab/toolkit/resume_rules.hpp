// Which configuration keys a run resumed from a restart file may change (docs/restart.md). A
// restart file records the configuration it was made with; a key whose value shaped what the file
// already holds (the specimen, the physics of a stage already run) must keep it, or the resumed run
// would mix two experiments in one history. Everything else (output intervals, the target strain,
// the next stage's parameters, threads) may change and is recorded as changed.
//
// Each key's rule is a column of its binding table (io::FixedAfter in io/config.hpp, the stage it
// is fixed from); these functions read it from the schema, and resume_rules_table() prints the
// table docs/restart.md shows, so that the rules are declared once.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <dem/io/config.hpp>

namespace dem::lab {

/// How far the run in a restart file got, in the order a run goes: the stages io::FixedAfter::from
/// numbers for the lab's protocols.
enum class RunProgress : int { Generating = 0, Generated, Consolidating, Consolidated, Shearing, Done };

/// "generating", "generated", ...: for messages.
std::string to_string(RunProgress progress);

/// A key's rule: fixed once the run has reached `from`, with `why` ending the refusal;
/// `reconsolidation`: a reconsolidation may change it anyway.
io::FixedAfter fixed_after(RunProgress from, std::string why, bool reconsolidation = false);

/// The rule of `key` in `schema`; std::logic_error for a key of the schema declared without one.
io::FixedAfter resume_rule(const io::Schema& schema, const std::string& key);

/// Every key of `config` with its value as text, exact (reals with 17 significant digits).
std::vector<std::pair<std::string, std::string>> configuration_record(const io::Config& config);

/// A key whose value differs between a restart file's record and this run's configuration.
struct ResumeChange {
  std::string key, file_value, new_value;
};

/// Compares a restart file's record with this run's (`now`, of `schema`): returns the changes the
/// rules allow, or throws dem::InputError naming every refused key with both values and why
/// (`where` names the file; `can_reconsolidate`: the refusal of a consolidated specimen points to
/// dem-consolidate). Keys only one of the records has (another version's schema) are left alone.
std::vector<ResumeChange> check_resume(const io::Schema& schema, const std::vector<std::pair<std::string, std::string>>& file_record,
                                       const std::vector<std::pair<std::string, std::string>>& now, RunProgress progress,
                                       bool reconsolidate, const std::string& where, bool can_reconsolidate = false);

/// docs/restart.md's table of `schema`'s rules, in Markdown: one row per rule, the keys that share it
/// (a whole section as `section.*`).
std::string resume_rules_table(const io::Schema& schema);

}  // namespace dem::lab
