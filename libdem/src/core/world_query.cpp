// Read-only views of a World: contacts, energies, the critical time step.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <dem/base/errors.hpp>
#include <dem/core/pair_geometry.hpp>
#include <dem/core/world.hpp>

namespace dem {

const PairContacts& World::pair_contacts(ContactKind kind) const {
  require_whole("pair_contacts()");
  require(kind != ContactKind::BallFacet, "pair_contacts kind", to_string(kind), "ball-ball or ball-pebble");
  return kind == ContactKind::BallBall ? state_.contacts.ball_ball : state_.contacts.ball_pebble;
}

namespace {

using ContactVisitor = std::function<void(const ContactView&)>;

/// Each touching contact of a pair set as a ContactView.
void visit_touching(const PairContacts& c, const ParticleStore& p, const ImageShifts* images, const ContactVisitor& visit) {
  // Lists just remade have no forces until the next step computes them: nothing to visit.
  for (std::size_t k = 0; k < c.size() && k < c.normal_force.size() && k < c.force.size(); ++k) {
    if (c.normal_force[k] <= 0.0) continue;
    const auto i = static_cast<std::size_t>(c.first[k]);
    const auto j = static_cast<std::size_t>(c.second[k]);
    const Vec3 d = contact_branch(c, k, p.x.data(), images);
    const double dist = d.norm();
    ContactView v{c.kind, i, static_cast<std::int64_t>(j), d / dist, Vec3::Zero(), c.force[k], c.normal_force[k]};
    v.image_shift = image_shift_of(c, k, images);
    const double overlap = p.radius[i] + p.radius[j] - dist;
    v.point = p.x[i] + (p.radius[i] - 0.5 * overlap) * v.normal;
    visit(v);
  }
}

/// Each touching contact of a wall set (facets or surfaces) as a ContactView of kind ball-facet.
void visit_touching(const WallContacts& c, const ParticleStore& p, const ContactVisitor& visit) {
  for (std::size_t k = 0; k < c.size() && k < c.normal_force.size() && k < c.force.size(); ++k) {
    if (c.normal_force[k] <= 0.0) continue;
    const auto i = static_cast<std::size_t>(c.ball[k]);
    const Vec3 arm = c.point[k] - p.x[i];
    visit(ContactView{ContactKind::BallFacet, i, c.wall[k], arm.normalized(), c.point[k], c.force[k], c.normal_force[k]});
  }
}

}  // namespace

void World::require_pair_records(const char* what) const {
  if (pair_records_current_) return;
  throw std::logic_error(std::string("World::") + what +
                         " read the contacts' forces on a step that did not record them: with "
                         "ContactRecords::WhenRead (the default) they are recorded on the last step of each step() "
                         "call and on the steps a callback follows; a controller that reads contacts during a step "
                         "needs World::set_contact_records(ContactRecords::EveryStep)");
}

void World::for_each_contact(const ContactVisitor& visit) const {
  require_whole("for_each_contact()");
  require_pair_records("for_each_contact()");
  std::optional<ImageShifts> images;  // a periodic cell's, for the positions now
  if (state_.cell) images = state_.cell->image_shifts();
  state_.contacts.for_each_set([&](const auto& set) {
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(set)>, PairContacts>)
      visit_touching(set, state_.particles, images ? &*images : nullptr, visit);
    else
      visit_touching(set, state_.particles, visit);
  });
}

std::size_t World::contact_count(ContactKind kind) const {
  require_whole("contact_count()");
  if (kind != ContactKind::BallFacet) require_pair_records("contact_count()");
  std::size_t count = 0;
  state_.contacts.for_each_set([&](const auto& set) {
    if (WorldContacts::law_kind(set) != kind) return;
    count += static_cast<std::size_t>(
        std::count_if(set.normal_force.begin(), set.normal_force.end(), [](double f) { return f > 0.0; }));
  });
  return count;
}

double World::kinetic_energy() const {
  require_whole("kinetic_energy()");
  const ParticleStore& p = state_.particles;
  double energy = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_pebble(i)) continue;
    energy += 0.5 * p.mass[i] * p.v[i].squaredNorm() + 0.5 / p.inv_inertia[i] * p.w[i].squaredNorm();
  }
  for (const Clump& c : state_.clumps) energy += 0.5 * c.mass * c.v.squaredNorm() + 0.5 * c.w.dot(c.inertia_world() * c.w);
  return energy;
}

double World::unbalanced_force_ratio() const {
  require_whole("unbalanced_force_ratio()");
  const ParticleStore& p = state_.particles;
  double unbalanced = 0.0;
  std::size_t balls = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_pebble(i) || p.fixed[i] == dof_all) continue;
    unbalanced += (p.f[i] + state_.settings.gravity * p.mass[i]).norm();
    ++balls;
  }
  double contact = 0.0;
  std::size_t contacts = 0;
  for_each_contact([&](const ContactView& c) {
    contact += c.normal_force;
    ++contacts;
  });
  if (balls == 0 || contacts == 0 || contact == 0.0) return std::numeric_limits<double>::infinity();
  return (unbalanced / static_cast<double>(balls)) / (contact / static_cast<double>(contacts));
}

double World::critical_time_step() const {
  const ParticleStore& p = state_.particles;
  const std::size_t n = p.size();
  std::vector<double> k_trans(n, 0.0), k_rot(n, 0.0);
  std::vector<double> clump_trans(state_.clumps.size(), 0.0), clump_rot(state_.clumps.size(), 0.0);

  auto add = [&](std::size_t i, const ContactStiffness& s, double arm) {
    if (p.is_pebble(i)) {
      const auto c = static_cast<std::size_t>(p.clump[i]);
      const double lever = (p.x[i] - state_.clumps[c].x).norm() + arm;
      clump_trans[c] += s.normal + s.shear;
      clump_rot[c] += s.shear * lever * lever + s.rolling;
    } else {
      k_trans[i] += s.normal + s.shear;
      k_rot[i] += s.shear * arm * arm + s.rolling;
    }
  };
  auto kinematics = [](ContactKind kind, double r1, double r2) {
    ContactKinematics k{};
    k.kind = kind;
    k.radius_1 = r1;
    k.radius_2 = r2;
    k.effective_radius = r2 > 0.0 ? r1 * r2 / (r1 + r2) : r1;
    k.normal = Vec3::UnitZ();
    return k;
  };
  // Each touching contact's stiffness on its pieces (a wall is rigid: only the ball). Not through
  // for_each_contact: this runs at rebuilds, inside a step, where the pair lists' force records
  // may be older (ContactRecords::WhenRead); `touching` is the last step's.
  state_.contacts.for_each_set([&](const auto& set) {
    const ContactKind kind = WorldContacts::law_kind(set);
    const ContactModel* model = contact_model(kind);
    if (model == nullptr) return;
    for (std::size_t k = 0; k < set.size(); ++k) {
      if constexpr (std::is_same_v<std::decay_t<decltype(set)>, PairContacts>) {
        if (k >= set.touching.size() || set.touching[k] == 0) continue;
        const auto i = static_cast<std::size_t>(set.first[k]);
        const auto j = static_cast<std::size_t>(set.second[k]);
        const ContactStiffness s = model->stiffness(kinematics(kind, p.radius[i], p.radius[j]));
        add(i, s, p.radius[i]);
        add(j, s, p.radius[j]);
      } else {
        if (k >= set.normal_force.size() || set.normal_force[k] <= 0.0) continue;
        const auto i = static_cast<std::size_t>(set.ball[k]);
        add(i, model->stiffness(kinematics(kind, p.radius[i], 0.0)), p.radius[i]);
      }
    }
  });
  // Each intact bond's stiffness on its balls (ParallelBondLaw::stiffness), as a contact's.
  const BondStore& bonds = state_.bonds;
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    if (!bonds.intact(k)) continue;
    const ContactStiffness s = ParallelBondLaw::stiffness(bonds.params(k));
    const std::size_t i = p.index_of(bonds.first[k]), j = p.index_of(bonds.second[k]);
    add(i, s, p.radius[i]);
    add(j, s, p.radius[j]);
  }

  double dt = std::numeric_limits<double>::infinity();
  double smallest = std::numeric_limits<double>::infinity();
  std::size_t smallest_index = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (p.is_pebble(i)) continue;
    if (k_trans[i] > 0.0) dt = std::min(dt, std::sqrt(p.mass[i] / k_trans[i]));
    if (k_rot[i] > 0.0) dt = std::min(dt, std::sqrt(1.0 / (p.inv_inertia[i] * k_rot[i])));
    if (p.radius[i] < smallest) smallest = p.radius[i], smallest_index = i;
  }
  for (std::size_t c = 0; c < state_.clumps.size(); ++c) {
    if (clump_trans[c] > 0.0) dt = std::min(dt, std::sqrt(state_.clumps[c].mass / clump_trans[c]));
    const double inertia = state_.clumps[c].inertia_body.diagonal().minCoeff();
    if (clump_rot[c] > 0.0) dt = std::min(dt, std::sqrt(inertia / clump_rot[c]));
  }
  // A ball with a single contact, so that a loose packing (no contacts yet) gets a time step too.
  if (std::isfinite(smallest)) {
    const double m = p.mass[smallest_index];
    for (ContactKind kind : {ContactKind::BallBall, ContactKind::BallFacet, ContactKind::BallPebble}) {
      const ContactModel* model = contact_model(kind);
      if (model == nullptr) continue;
      const ContactStiffness s =
          model->stiffness(kinematics(kind, smallest, kind == ContactKind::BallFacet ? 0.0 : smallest));
      dt = std::min(dt, std::sqrt(m / (s.normal + s.shear)));
    }
  }
  return dt;
}

}  // namespace dem
