#include <dem/lab/toolkit/resume_rules.hpp>

#include <algorithm>
#include <map>
#include <sstream>
#include <stdexcept>

#include <dem/core/errors.hpp>

namespace dem::lab {

using P = RunProgress;

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

io::FixedAfter fixed_after(RunProgress from, std::string why, bool reconsolidation) {
  return {static_cast<int>(from), std::move(why), reconsolidation};
}

io::FixedAfter resume_rule(const io::Schema& schema, const std::string& key) {
  const io::KeySpec* spec = schema.find(key);
  if (!spec || !spec->fixed) throw std::logic_error("resume rule: configuration key '" + key + "' has none (its binding table's fixed column)");
  return *spec->fixed;
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
      {"ball_ball.rolling", "epsd"},  // Hertz-Mindlin's one rolling model before the key
      {"ball_facet.rolling", "epsd"},
      {"ball_pebble.rolling", "epsd"},
      {"ball_ball.rolling_stiffness", "0"},  // sds's spring, added after cdt
      {"ball_facet.rolling_stiffness", "0"},
      {"ball_pebble.rolling_stiffness", "0"},
  };
  return values;
}

// Defaults an earlier libdem had, with the date they changed: a file whose run used the old one
// (the user may never have set the key) is refused with the --set that resumes it.
struct EarlierDefault {
  const char* value;
  const char* until;
};
const std::map<std::string, EarlierDefault>& earlier_defaults() {
  static const std::map<std::string, EarlierDefault> values = {
      {"specimen.porosity", {"0.4", "2026-12-07"}},  // 0.46 since (docs/size-effect.md)
  };
  return values;
}

}  // namespace

std::vector<ResumeChange> check_resume(const io::Schema& schema, const std::vector<std::pair<std::string, std::string>>& file_record,
                                       const std::vector<std::pair<std::string, std::string>>& now, RunProgress progress,
                                       bool reconsolidate, const std::string& where, bool can_reconsolidate) {
  std::map<std::string, std::string> before(file_record.begin(), file_record.end());
  if (!before.empty())  // a file with no record at all gets only the older specimen checks
    for (const auto& [key, value] : values_before_keys()) before.emplace(key, value);
  std::vector<ResumeChange> allowed;
  std::ostringstream refused;
  int refusals = 0;
  for (const auto& [key, value] : now) {
    const auto it = before.find(key);
    if (it == before.end() || it->second == value || !schema.find(key)) continue;
    const io::FixedAfter rule = resume_rule(schema, key);
    const bool may = rule.is_never() || static_cast<int>(progress) < rule.from ||
                     (reconsolidate && rule.reconsolidation && progress == P::Consolidated);
    if (may) {
      allowed.push_back({key, it->second, value});
      continue;
    }
    refused << (refusals++ ? "; " : "") << key << " = " << value << " here, " << it->second << " in the file (" << rule.why
            << ")";
    if (const auto old = earlier_defaults().find(key); old != earlier_defaults().end() && it->second == old->second.value)
      refused << " [" << it->second << " was the default until " << old->second.until << ": --set " << key << "="
              << it->second << " resumes the file]";
  }
  if (refusals > 0) {
    std::string hint = "resume with the file's values (the same --preset, --config and --set)";
    if (progress == P::Consolidated && !reconsolidate && can_reconsolidate)
      hint += ", or consolidate the specimen again with new contact parameters: dem-consolidate --from the file";
    throw InputError(where + ": the run was " + to_string(progress) + " and " + std::to_string(refusals) +
                     " key(s) would change what it already did: " + refused.str() + ". Allowed: " + hint +
                     " (docs/restart.md lists which keys may change)");
  }
  return allowed;
}

}  // namespace dem::lab

namespace dem::lab {

std::string resume_rules_table(const io::Schema& schema) {
  // The keys of each rule, in schema order; a section whose keys all share one rule is one entry.
  struct Row {
    io::FixedAfter rule;
    std::vector<std::string> keys;
  };
  std::vector<Row> rows;
  const auto same = [](const io::FixedAfter& a, const io::FixedAfter& b) {
    return a.from == b.from && a.why == b.why && a.reconsolidation == b.reconsolidation;
  };
  const auto& keys = schema.keys();
  for (std::size_t k = 0; k < keys.size();) {
    const std::string section = keys[k].key.substr(0, keys[k].key.find('.'));
    std::size_t end = k;
    bool one_rule = true;
    while (end < keys.size() && keys[end].key.rfind(section + ".", 0) == 0) one_rule = one_rule && same(resume_rule(schema, keys[end].key), resume_rule(schema, keys[k].key)), ++end;
    for (std::size_t j = k; j < end; j = one_rule ? end : j + 1) {
      const io::FixedAfter rule = resume_rule(schema, keys[j].key);
      const std::string name = "`" + (one_rule ? section + ".*" : keys[j].key) + "`";
      auto row = std::find_if(rows.begin(), rows.end(), [&](const Row& r) { return same(r.rule, rule); });
      if (row == rows.end()) rows.push_back({rule, {name}});
      else row->keys.push_back(name);
    }
    k = end;
  }
  std::stable_sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.rule.from < b.rule.from; });
  static const char* const stages[] = {"started (any restart file)", "been generated", "begun the consolidation", "been consolidated",
                                       "begun the shear (or the cyclic stage)", "finished"};
  std::ostringstream out;
  out << "| keys | fixed once the run has | why |\n|---|---|---|\n";
  for (const Row& r : rows) {
    std::string names;
    for (const std::string& n : r.keys) names += (names.empty() ? "" : ", ") + n;
    const bool never = r.rule.is_never();
    std::string when = never ? "never" : stages[std::clamp(r.rule.from, 0, 5)];
    if (!never && r.rule.reconsolidation) when += " (a reconsolidation may change them)";
    out << "| " << names << " | " << when << " | " << (never ? "outputs, the end of the run, stop criteria and threads change no physics already done" : r.rule.why) << " |\n";
  }
  return out.str();
}

}  // namespace dem::lab
