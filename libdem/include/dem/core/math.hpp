// The Eigen aliases live on the ground floor, dem/base/math.hpp; this name stays for the code that
// includes it.
#pragma once

#include <dem/base/math.hpp>
