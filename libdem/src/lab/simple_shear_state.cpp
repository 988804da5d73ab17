// The protocol's progress in a restart file: a JSON object (keys as below) written by
// protocol_state(), read back by restore_protocol_state() through read_protocol_record
// (lab/specimen_file.hpp), which also reads the "key value" lines of files written before.
#include <dem/lab/simple_shear.hpp>

#include <dem/core/errors.hpp>
#include <dem/lab/specimen_file.hpp>

#include "../io/json_file.hpp"

namespace dem::lab {

std::string SimpleShearTest::protocol_state() const {
  io::Json j;
  j["stage"] = static_cast<int>(stage_);
  j["ball_count"] = ball_count_;
  j["generated_porosity"] = generated_porosity_;
  j["consolidated_height"] = consolidated_height_;
  j["leg"] = leg_;
  j["leg_start_strain"] = leg_start_strain_;
  j["path_strain"] = path_.strain();
  j["next_output_strain"] = next_output_strain_;
  j["next_fabric"] = next_fabric_;
  j["next_snapshot"] = next_snapshot_;
  j["last_restart_step"] = last_restart_step_;
  j["previous_relative_x"] = path_.offset().x();
  j["previous_relative_y"] = path_.offset().y();
  j["wall_seconds"] = wall_seconds_;
  j["steps_at_shear_start"] = steps_at_shear_start_;
  j["history_rows"] = history_.rows();
  j["servo"] = servo_ != nullptr;
  j["servo_holding"] = servo_ && servo_->holding_position();
  if (servo_) {
    j["servo_target"] = servo_->settings().target_stress;
    j["servo_max_speed"] = servo_->settings().max_speed;
    j["servo_steps_on_target"] = servo_->steps_on_target();
  }
  // Generation and consolidation in progress (restart files written during them).
  j["generating"] = generating_;
  j["generation_floor"] = generation_floor_;
  j["generation_phase"] = generation_.phase;
  j["generation_stage"] = generation_.stage;
  j["generation_increment"] = generation_.increment;
  j["generation_settled_steps"] = generation_.settled_steps;
  j["friction_now"] = friction_now_;
  j["rolling_friction_now"] = rolling_friction_now_;
  j["consolidating"] = consolidating_;
  j["consolidation_start_step"] = consolidation_start_step_;
  const ProfileInterval& interval = uniformity_->interval();
  for (const auto& [end, x] : {std::pair{"bottom", &interval.bottom}, std::pair{"top", &interval.top}}) {
    const std::string name = std::string("profile_") + end;
    j[name + "_x"] = x->x();
    j[name + "_y"] = x->y();
    j[name + "_z"] = x->z();
  }
  for (const auto& [name, state] : {std::pair{"specimen_generated", &generated_state_}, std::pair{"specimen_consolidated", &consolidated_state_}}) {
    const std::string n = name;
    j[n + "_porosity"] = state->porosity;
    j[n + "_sphere_porosity"] = state->sphere_porosity;
    j[n + "_coordination"] = state->coordination_number;
    j[n + "_mechanical_coordination"] = state->mechanical_coordination_number;
    j[n + "_vertical_stress"] = state->vertical_stress;
    j[n + "_k0"] = state->k0;
    j[n + "_height"] = state->height;
    j[n + "_friction"] = state->friction;
    j[n + "_rolling_friction"] = state->rolling_friction;
  }
  // The configuration the file was made with (record_configuration), key: value text.
  io::Json& record = j["configuration"] = io::Json::object();
  for (const auto& [key, value] : configuration_) record[key] = value;
  // Last: the positions that start the current profile interval, by ball id (null for pebbles).
  io::Json& reference = j["profile_reference"] = io::Json::array();
  for (const Vec3& x : interval.positions) reference.push_back({x.x(), x.y(), x.z()});
  // One line: a 1D specimen has 10^5 reference positions. Invalid UTF-8 in a text is replaced, not
  // thrown on in the middle of a run.
  return j.dump(-1, ' ', false, io::Json::error_handler_t::replace) + "\n";
}

void SimpleShearTest::restore_protocol_state(const std::string& text) {
  ProtocolRecord record = read_protocol_record(text);
  file_configuration_ = std::move(record.configuration);
  ProfileInterval interval;
  interval.positions = std::move(record.profile_reference);
  const auto get = [&](const std::string& k) { return record.number(k); };
  stage_ = static_cast<ShearStage>(static_cast<int>(get("stage")));
  ball_count_ = static_cast<std::size_t>(get("ball_count"));
  generated_porosity_ = get("generated_porosity");
  consolidated_height_ = get("consolidated_height");
  leg_ = static_cast<std::size_t>(get("leg"));
  leg_start_strain_ = get("leg_start_strain");
  next_output_strain_ = get("next_output_strain");
  next_fabric_ = static_cast<std::size_t>(get("next_fabric"));
  next_snapshot_ = static_cast<std::size_t>(get("next_snapshot"));
  last_restart_step_ = static_cast<std::int64_t>(get("last_restart_step"));
  path_ = ShearPath(consolidated_height_, get("path_strain"), Vec3(get("previous_relative_x"), get("previous_relative_y"), 0.0));
  wall_seconds_ = get("wall_seconds");
  steps_at_shear_start_ = static_cast<std::int64_t>(get("steps_at_shear_start"));
  if (record.has("profile_bottom_x")) {
    interval.bottom = Vec3(get("profile_bottom_x"), get("profile_bottom_y"), get("profile_bottom_z"));
    interval.top = Vec3(get("profile_top_x"), get("profile_top_y"), get("profile_top_z"));
  }
  uniformity_->resume_interval(std::move(interval));
  // Files written before these were recorded leave them NaN.
  const auto optional = [&](const std::string& k) { return record.number_or_nan(k); };
  for (const auto& [name, state] : {std::pair{"specimen_generated", &generated_state_}, std::pair{"specimen_consolidated", &consolidated_state_}}) {
    const std::string n = name;
    *state = {optional(n + "_porosity"), optional(n + "_sphere_porosity"), optional(n + "_coordination"),
              optional(n + "_mechanical_coordination"), optional(n + "_vertical_stress"), optional(n + "_k0"),
              optional(n + "_height"), optional(n + "_friction"), optional(n + "_rolling_friction")};
  }
  // Keep the history written up to the restart point; later rows belong to the run that stopped.
  history_.resume(restart_folder_ / "history.csv", static_cast<std::size_t>(get("history_rows")));
  if (get("servo") > 0) {
    servo_ = std::make_shared<ServoWall>(cell_.top, recorded_servo(record, servo_settings()));
    servo_->hold_position(get("servo_holding") > 0);
    if (record.has("servo_steps_on_target")) servo_->resume_steps_on_target(recorded_steps_on_target(record));
  }
  const auto flag = [&](const std::string& k) { return record.flag(k); };
  generating_ = flag("generating");
  generation_floor_ = flag("generation_floor");
  consolidating_ = flag("consolidating");
  if (generating_) {
    generation_.phase = static_cast<int>(get("generation_phase"));
    generation_.stage = static_cast<int>(get("generation_stage"));
    generation_.increment = static_cast<int>(get("generation_increment"));
    generation_.settled_steps = static_cast<long>(get("generation_settled_steps"));
    require(generation_.phase >= GenerationProgress::Expanding && generation_.phase <= GenerationProgress::ScheduleSettle,
            "restart file: generation_phase", generation_.phase, "0 to 4");
    require(generation_.stage >= 1 && generation_.increment >= 0 && generation_.increment <= 10 && generation_.settled_steps >= 0,
            "restart file: generation_stage, generation_increment, generation_settled_steps",
            std::to_string(generation_.stage) + ", " + std::to_string(generation_.increment) + ", " +
                std::to_string(generation_.settled_steps),
            "a stage >= 1, an increment in 0..10 and a step count >= 0");
    friction_now_ = get("friction_now");
    rolling_friction_now_ = get("rolling_friction_now");
  }
  if (record.has("consolidation_start_step")) consolidation_start_step_ = static_cast<std::int64_t>(get("consolidation_start_step"));
}
}  // namespace dem::lab
