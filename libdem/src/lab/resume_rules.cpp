#include <dem/lab/resume_rules.hpp>

#include <map>
#include <sstream>
#include <stdexcept>

#include <dem/core/errors.hpp>

namespace dem::lab {

namespace {

using P = RunProgress;

ResumeRule fixed(P from, std::string why, bool reconsolidation = false) { return {from, false, reconsolidation, std::move(why)}; }
ResumeRule free_key() { return {P::Done, true, true, ""}; }

// One rule per key or per section ("section." applies to every key of it); a key's own rule wins.
// docs/restart.md prints this table for users: change both together.
const std::map<std::string, ResumeRule>& rules() {
  static const std::map<std::string, ResumeRule> table = [] {
    std::map<std::string, ResumeRule> t;
    const std::string specimen = "the specimen was made with it";
    for (const char* section : {"specimen.", "grading.", "generation."}) t[section] = fixed(P::Generating, specimen);
    for (const char* key : {"rings.pebble_diameter", "rings.gap", "rings.density", "rings.stack_height"})
      t[key] = fixed(P::Generating, "the ring stack was built with it");
    t["rings.vertical"] = fixed(P::Shearing, "the shear so far moved the rings this way");
    t["engine.local_damping"] = fixed(P::Generating, "every step so far was damped with it");
    t["engine.time_step"] = fixed(P::Generating, "every step so far used it", true);
    t["engine.time_step_safety"] = fixed(P::Generating, "the time step so far was set with it", true);
    t["engine.max_overlap_ratio"] = free_key();
    t["engine.threads"] = free_key();
    // Contact stiffness and damping act from the first step; the friction of the final contacts
    // from the consolidation on (the generation uses generation.friction, frictionless walls).
    for (const char* section : {"ball_ball.", "ball_facet.", "ball_pebble."}) {
      const std::string s = section;
      t[s + "law"] = fixed(P::Generating, "the contacts so far had it");
      for (const char* name : {"effective_modulus", "stiffness_ratio", "normal_damping_ratio", "shear_damping_ratio"})
        t[s + name] = fixed(P::Generating, "the contacts so far had it", true);
      for (const char* name : {"friction", "rolling_friction"})
        t[s + name] = fixed(P::Consolidating, "the consolidation ran with it", true);
    }
    t["consolidation."] = fixed(P::Consolidating, "the consolidation ran with it", true);
    t["shear."] = fixed(P::Shearing, "the shear so far ran with it");
    t["shear.target_strain"] = free_key();
    t["measure."] = fixed(P::Consolidated, "history.csv so far was measured with it");
    t["output.volumetric_strain_sign"] = fixed(P::Consolidated, "history.csv so far was written with it");
    for (const char* key : {"output.every_strain", "output.fabric_strains", "output.snapshot_strains",
                            "output.restart_every_steps", "output.progress_seconds"})
      t[key] = free_key();
    // The cyclic stage starts from a consolidated specimen and is not resumed mid-way.
    t["cyclic."] = free_key();
    return t;
  }();
  return table;
}

}  // namespace

std::string to_string(RunProgress progress) {
  switch (progress) {
    case P::Generating: return "generating";
    case P::Generated: return "generated";
    case P::Consolidating: return "consolidating";
    case P::Consolidated: return "consolidated";
    case P::Shearing: return "shearing";
    case P::Done: return "done";
  }
  return "?";
}

ResumeRule resume_rule(const std::string& key) {
  const auto& t = rules();
  if (const auto it = t.find(key); it != t.end()) return it->second;
  if (const auto dot = key.find('.'); dot != std::string::npos)
    if (const auto it = t.find(key.substr(0, dot + 1)); it != t.end()) return it->second;
  throw std::logic_error("resume_rule: no rule for configuration key '" + key + "' (lab/resume_rules.cpp)");
}

std::vector<std::pair<std::string, std::string>> configuration_record(const io::Config& config) {
  std::vector<std::pair<std::string, std::string>> record;
  for (const io::KeySpec& spec : config.schema().keys()) record.emplace_back(spec.key, config.exact_text(spec.key));
  return record;
}

namespace {

// Keys added after restart files were first written, with the value such a file's run had: a file
// without the key is checked as if it held that value, so that a new default cannot slip into a
// stage the file has already run.
const std::map<std::string, std::string>& values_before_keys() {
  static const std::map<std::string, std::string> values = {
      {"shear.damping_frame", "fixed"},  // shear legs were damped in the fixed frame (docs/model.md 3.1)
      {"ball_ball.law", "rrlinear"},  // the one law of the contact types before the registry
      {"ball_facet.law", "rrlinear"},
      {"ball_pebble.law", "rrlinear"},
  };
  return values;
}

}  // namespace

std::vector<ResumeChange> check_resume(const std::vector<std::pair<std::string, std::string>>& file_record,
                                       const std::vector<std::pair<std::string, std::string>>& now, RunProgress progress,
                                       bool reconsolidate, const std::string& where) {
  std::map<std::string, std::string> before(file_record.begin(), file_record.end());
  if (!before.empty())  // a file with no record at all gets only the older specimen checks
    for (const auto& [key, value] : values_before_keys()) before.emplace(key, value);
  std::vector<ResumeChange> allowed;
  std::ostringstream refused;
  int refusals = 0;
  for (const auto& [key, value] : now) {
    const auto it = before.find(key);
    if (it == before.end() || it->second == value) continue;
    const ResumeRule rule = resume_rule(key);
    const bool may = rule.never_fixed || static_cast<int>(progress) < static_cast<int>(rule.fixed_from) ||
                     (reconsolidate && rule.reconsolidation_may_change && progress == P::Consolidated);
    if (may) {
      allowed.push_back({key, it->second, value});
      continue;
    }
    refused << (refusals++ ? "; " : "") << key << " = " << value << " here, " << it->second << " in the file (" << rule.why
            << ")";
  }
  if (refusals > 0) {
    std::string hint = "resume with the file's values (the same --preset, --config and --set)";
    if (progress == P::Consolidated && !reconsolidate)
      hint += ", or consolidate the specimen again with new contact parameters: dem-consolidate --from the file";
    throw InputError(where + ": the run was " + to_string(progress) + " and " + std::to_string(refusals) +
                     " key(s) would change what it already did: " + refused.str() + ". Allowed: " + hint +
                     " (docs/restart.md lists which keys may change)");
  }
  return allowed;
}

}  // namespace dem::lab
