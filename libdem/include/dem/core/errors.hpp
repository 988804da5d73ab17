// The error types live on the ground floor, dem/base/errors.hpp; this name stays for the code that
// includes it.
#pragma once

#include <dem/base/errors.hpp>
