#include <dem/lab/toolkit/consolidation.hpp>

namespace dem::lab {

void start_consolidation(ServoWall& servo, const ConsolidationTarget& target) {
  servo.set_target(target.vertical_stress);
  servo.set_max_speed(target.servo_max_speed);
}

ConsolidationReport consolidate(World& world, const ServoWall& servo, const ConsolidationTarget& target,
                                std::int64_t start_step, const std::function<void()>& between_chunks) {
  ConsolidationReport report;
  while (world.step_count() - start_step < target.max_steps) {
    world.step(target.chunk_steps);
    report.settled = servo.settled() && world.unbalanced_force_ratio() < target.equilibrium_ratio;
    if (report.settled) break;
    if (between_chunks) between_chunks();
  }
  report.steps = world.step_count() - start_step;
  report.stress = servo.achieved_stress();
  report.unbalanced_ratio = world.unbalanced_force_ratio();
  return report;
}

}  // namespace dem::lab
