#include <dem/lab/toolkit/run.hpp>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <sstream>

#include <dem/core/errors.hpp>
#include <dem/io/checkpoint.hpp>

#include "../../io/json_file.hpp"

namespace dem::lab {

namespace {

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

bool same_folder(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code error;
  const bool same = std::filesystem::equivalent(a, b, error);
  return !error && same;
}

// The carried files of a run resumed from a restart written in another folder, brought here (hard
// links where possible: they are only read, and every writer replaces files by renaming, which
// leaves the originals alone). The resumed run trims them to the restart point, as it does in the
// restart's own folder. A folder's files are brought one by one: a user's file in the folder here
// stays. Returns the files brought into folders (the named ones are listed at claim already).
std::vector<std::filesystem::path> copy_carried(const std::filesystem::path& from, const std::filesystem::path& to,
                                                const std::vector<std::string>& names) {
  namespace fs = std::filesystem;
  fs::create_directories(to);
  std::vector<fs::path> inner;
  const auto bring = [](const fs::path& source, const fs::path& target) {
    fs::remove(target);
    std::error_code linked;
    fs::create_hard_link(source, target, linked);
    if (linked) fs::copy_file(source, target);
  };
  for (const std::string& name : names) {
    if (!fs::exists(from / name)) continue;
    if (!fs::is_directory(from / name)) {
      fs::copy_file(from / name, to / name, fs::copy_options::overwrite_existing);
      continue;
    }
    for (const auto& entry : fs::recursive_directory_iterator(from / name)) {
      const fs::path target = to / name / entry.path().lexically_relative(from / name);
      if (entry.is_directory()) {
        fs::create_directories(target);
        continue;
      }
      fs::create_directories(target.parent_path());
      bring(entry.path(), target);
      inner.push_back(target);
    }
  }
  return inner;
}

}  // namespace

Run::Run(std::unique_ptr<World> world, std::filesystem::path folder, RunFiles files, std::ostream& log)
    : world_(std::move(world)), folder_(std::move(folder)), files_(std::move(files)), log_(&log) {
  require(world_ != nullptr, "Run: world", "null", "a World");
  keep("last_restart_step", last_restart_step_);
  keep("wall_seconds", wall_seconds_);
}

void Run::claim(const OutputOptions& options) {
  require(!folder_claim_, "the output folder " + folder_.string(), "claimed twice", "claimed once per run");
  const bool own = loaded() && same_folder(loaded_from_, folder_);
  namespace fs = std::filesystem;
  if (own) {
    // A run that ended (final.restart) and is run again from an earlier restart file in its own
    // folder would leave two runs' files side by side until the new one ends, or for good if it
    // is stopped. Going on from final.restart itself (a longer shear) is the same run.
    if (loaded_name_ != "final.restart" && fs::exists(folder_ / "final.restart"))
      throw InputError("--from " + (folder_ / loaded_name_).string() + " into its own folder " + folder_.string() +
                       ", which holds a run that ended (final.restart): run it again into another --out folder (the "
                       "files up to " + loaded_name_ + " are carried there), or go on from final.restart");
  }
  io::OutputFolderPolicy policy;
  policy.replace = options.replace;
  policy.continues_own_run = own;
  policy.run_files = files_.results;
  policy.run_files.insert(policy.run_files.end(), options.more_run_files.begin(), options.more_run_files.end());
  policy.replace_option = options.replace_option;
  policy.program = options.program;
  folder_claim_ = std::make_unique<io::OutputFolder>(folder_, policy);
  for (const std::string& name : folder_claim_->replaced()) *log_ << "removed " << (folder_ / name).string() << " of the run the folder held\n";
  if (folder_claim_->leftovers_removed() > 0)
    *log_ << "removed " << folder_claim_->leftovers_removed() << " temporary file(s) left by a killed run\n";
  if (loaded() && !own) record_outputs(copy_carried(loaded_from_, folder_, files_.carried));
  // The summary of the session before is not this run's: until this one ends the folder has none.
  if (own && std::find(files_.results.begin(), files_.results.end(), "summary.json") != files_.results.end())
    fs::remove(folder_ / "summary.json");
  for (const auto& f : on_claim_) f();
}

void Run::record_outputs(const std::vector<std::filesystem::path>& files) {
  if (!folder_claim_) return;
  for (const auto& file : files) folder_claim_->record(file);
}

void Run::keep(const std::string& key, double& value) {
  kept_.push_back({key, [&value] { return value; }, [&value](double v) { value = v; }});
  restore(kept_.back());
}

namespace {

// A count or index read from a restart file: a whole number within `lowest` and 2^53 (a file whose
// checksum holds can still carry any value a program wrote; a cast of 1e308 is undefined).
double whole_number(const std::string& key, double v, double lowest) {
  require(std::isfinite(v) && v == std::floor(v) && v >= lowest && v <= 9007199254740992.0, "restart file: " + key, v,
          "a whole number from " + std::to_string(static_cast<long long>(lowest)) + " to 2^53");
  return v;
}

}  // namespace

void Run::keep(const std::string& key, std::int64_t& value) {
  kept_.push_back({key, [&value] { return static_cast<double>(value); },
                   [&value, key](double v) { value = static_cast<std::int64_t>(whole_number(key, v, -1.0)); }, true});
  restore(kept_.back());
}

void Run::keep(const std::string& key, int& value) {
  kept_.push_back({key, [&value] { return static_cast<double>(value); }, [&value, key](double v) {
                     require(v <= 2147483647.0, "restart file: " + key, v, "at most 2147483647");
                     value = static_cast<int>(whole_number(key, v, -1.0));
                   }, true});
  restore(kept_.back());
}

void Run::keep(const std::string& key, std::size_t& value) {
  kept_.push_back({key, [&value] { return static_cast<double>(value); },
                   [&value, key](double v) { value = static_cast<std::size_t>(whole_number(key, v, 0.0)); }, true});
  restore(kept_.back());
}

void Run::keep(const std::string& key, bool& value) {
  kept_.push_back({key, [&value] { return value ? 1.0 : 0.0; }, [&value](double v) { value = v > 0; }, false, true});
  restore(kept_.back());
}

void Run::keep(const std::string& key, std::function<double()> save, std::function<void(double)> restore_value) {
  kept_.push_back({key, std::move(save), std::move(restore_value)});
  restore(kept_.back());
}

void Run::keep_points(const std::string& key, std::vector<Vec3>& points) {
  kept_points_.emplace_back(key, &points);
  if (const auto it = record_.points.find(key); loaded() && it != record_.points.end()) points = it->second;
}

void Run::restore(const Kept& kept) const {
  // A key the file lacks (written by an older version) leaves the value as the protocol set it.
  if (loaded() && record_.has(kept.key)) kept.restore(record_.number(kept.key));
}

void Run::step(std::int64_t steps, World::StepEnd end) {
  world_->step(steps, end);
  save_if_due();
}

void Run::save_if_due() {
  if (world_->step_count() - last_restart_step_ < restart_every_) return;
  last_restart_step_ = world_->step_count();
  world_->gather_state();  // after a step that left only the walls whole
  save(folder_ / "restart.restart");
}

std::string Run::cursor_text() const {
  io::Json j;
  for (const Kept& k : kept_) {
    const double v = k.save();
    if (k.flag) j[k.key] = v > 0;
    else if (k.integer) j[k.key] = static_cast<std::int64_t>(v);
    else j[k.key] = v;
  }
  // The configuration the file was made with (record_configuration), key: value text.
  io::Json& record = j["configuration"] = io::Json::object();
  for (const auto& [key, value] : configuration_) record[key] = value;
  for (const auto& [key, points] : kept_points_) {
    io::Json& list = j[key] = io::Json::array();
    for (const Vec3& x : *points) list.push_back({x.x(), x.y(), x.z()});
  }
  // One line: a 1D specimen keeps 10^5 positions. Invalid UTF-8 in a text is replaced, not
  // thrown on in the middle of a run.
  return j.dump(-1, ' ', false, io::Json::error_handler_t::replace) + "\n";
}

void Run::save(const std::filesystem::path& file) const { io::save_checkpoint(file, *world_, cursor_text()); }

const ProtocolRecord& Run::load(const std::filesystem::path& file) {
  require(!folder_claim_, "loading " + file.string() + " after the output folder was claimed", file.string(),
          "a restart loaded before any stage ran");
  require(!loaded(), "loading a second restart file", file.string(), "one restart file per run");
  record_ = read_protocol_record(io::load_checkpoint(file, *world_), "restart file " + file.string());
  loaded_from_ = std::filesystem::absolute(file).parent_path();
  loaded_name_ = file.filename().string();
  loaded_step_ = world_->step_count();
  for (const Kept& k : kept_) restore(k);
  for (const auto& [key, points] : kept_points_)
    if (const auto it = record_.points.find(key); it != record_.points.end()) *points = it->second;
  for (const auto& f : on_load_) f();
  return record_;
}

void Run::record_configuration(const io::Config& resolved) {
  schema_ = resolved.schema();
  configuration_.clear();
  for (const io::KeySpec& spec : resolved.schema().keys()) configuration_.emplace_back(spec.key, resolved.exact_text(spec.key));
}

void Run::note_change(const std::string& key, const std::string& file_value, const std::string& new_value) {
  *log_ << "applied " << key << " = " << new_value << " (the restart file had " << file_value << ")\n";
  changes_.push_back({key, file_value, new_value});
}

void Run::progress(const std::string& stage, const std::string& detail, double done, double total) {
  const double now = now_seconds();
  if (stage != pace_stage_) pace_stage_ = stage, pace_start_seconds_ = now, pace_start_done_ = done;
  if (now - last_progress_ < progress_every_) return;
  last_progress_ = now;
  *log_ << "[" << stage << "] " << detail;
  if (total >= 0.0) {
    // Time left from this session's own pace in the stage, over what is still to do.
    const double progressed = done - pace_start_done_, left = std::max(0.0, total - done);
    *log_ << ", " << (progressed > 0 ? (now - pace_start_seconds_) * left / progressed : 0.0) << " s left";
  }
  *log_ << std::endl;
}

}  // namespace dem::lab
