// libdem: everything a simulation needs, in one include.
#pragma once

#include <dem/base/errors.hpp>
#include <dem/base/math.hpp>
#include <dem/boundary/clump.hpp>
#include <dem/boundary/clump_ring.hpp>
#include <dem/boundary/wall.hpp>
#include <dem/contact/contact_law.hpp>
#include <dem/contact/hertz_dmt_law.hpp>
#include <dem/contact/hertz_mindlin_law.hpp>
#include <dem/contact/linear_law.hpp>
#include <dem/contact/parallel_bond.hpp>
#include <dem/control/cell_servo.hpp>
#include <dem/control/servo_wall.hpp>
#include <dem/core/contact_loops.hpp>  // make_contact_model for a law of your own
#include <dem/core/contact_model.hpp>
#include <dem/core/particles.hpp>
#include <dem/core/world.hpp>
#include <dem/geometry/mesh.hpp>
#include <dem/geometry/triangle.hpp>
#include <dem/measure/cell_state.hpp>
#include <dem/measure/cell_stress.hpp>
#include <dem/measure/measurement_sphere.hpp>
#include <dem/measure/principal_stress.hpp>
