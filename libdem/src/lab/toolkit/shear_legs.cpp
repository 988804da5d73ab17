#include <dem/lab/toolkit/shear_legs.hpp>

#include <cmath>

#include <dem/core/errors.hpp>

namespace dem::lab {

ShearLegs::ShearLegs(std::vector<ShearLeg> legs) : legs_(std::move(legs)) {
  require(!legs_.empty(), "shear legs", "(none)", "at least one leg");
}

void ShearLegs::keep_in(Run& run, std::function<double()> height) {
  // Range-checked: a leg past the last, or a strain of 1e308, would end the run without shearing
  // or step it forever. Strains beyond 100 (10,000 %) are no simple shear.
  const auto strain = [](const std::string& key, double v) {
    require(std::isfinite(v) && std::abs(v) <= 100.0, "restart file: " + key, v, "a strain from -100 to 100");
    return v;
  };
  run.keep("leg", leg_);
  run.on_load([this] {
    require(leg_ <= legs_.size(), "restart file: leg", leg_,
            "a leg from 0 to " + std::to_string(legs_.size()) + " (the configuration's shear legs)");
  });
  run.keep("leg_start_strain", [this] { return leg_start_strain_; },
           [this, strain](double v) { leg_start_strain_ = strain("leg_start_strain", v); });
  run.keep("path_strain", [this] { return path_.strain(); }, [this, strain](double v) { loaded_.x() = strain("path_strain", v); });
  run.keep("previous_relative_x", [this] { return path_.offset().x(); }, [this](double v) { loaded_.y() = v; });
  run.keep("previous_relative_y", [this] { return path_.offset().y(); }, [this](double v) { loaded_.z() = v; });
  run.on_load([this, height] { path_ = ShearPath(height(), loaded_.x(), Vec3(loaded_.y(), loaded_.z(), 0.0)); });
}

void ShearLegs::start(const World& world, const ShearCell& cell, double height) {
  leg_ = 0;
  leg_start_strain_ = 0.0;
  path_ = ShearPath(world, cell, height);
}

double ShearLegs::total_strain() const {
  double total = 0.0;
  for (const ShearLeg& leg : legs_) total += leg.strain;
  return total;
}

void ShearLegs::run(World& world, const ShearCell& cell, std::int64_t chunk_steps,
                    const std::function<void(const ShearLeg&)>& start_leg,
                    const std::function<void(double strain, bool done)>& after_chunk) {
  while (leg_ < legs_.size()) {
    world.step(chunk_steps, World::StepEnd::WallsAndClumps);
    path_.advance(world, cell);
    if (path_.strain() - leg_start_strain_ >= legs_[leg_].strain * (1 - 1e-12)) {
      leg_start_strain_ += legs_[leg_].strain;
      ++leg_;
      if (leg_ < legs_.size()) start_leg(legs_[leg_]);
    }
    after_chunk(path_.strain(), leg_ == legs_.size());
  }
}

}  // namespace dem::lab
