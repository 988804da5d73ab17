// Principal stresses and their orientation, for the study's stress-rotation plots (docs/model.md 6.3).
//
// Input is the measured stress in the continuum convention (tension positive, as PFC reports
// it); output is compression positive, as soil papers and the study's figures use. The sign flip
// happens here, once, so callers never mix the two conventions.
//
// The in-plane rotation angles come from the 2x2 sub-tensors (closed form), not from the 3-D
// eigenvectors: in bi-directional shear the 3-D major direction leaves the x-z plane, and the
// study's psi is defined on the x-z components alone.
#pragma once

#include <dem/core/math.hpp>

namespace dem::measure {

/// Principal values and directions of a stress tensor, compression positive.
struct PrincipalStresses {
  double sigma_1;  ///< major principal stress, Pa (compression positive)
  double sigma_2;  ///< intermediate principal stress, Pa
  double sigma_3;  ///< minor principal stress, Pa; sigma_1 >= sigma_2 >= sigma_3
  /// Unit eigenvectors of sigma_1, sigma_2, sigma_3. Each sign is chosen so that the vector
  /// points upwards (z > 0); a horizontal one points towards +x, or +y if along y. The three
  /// therefore need not form a right-handed frame. For repeated eigenvalues any orthonormal
  /// basis of the eigenspace may be returned.
  Vec3 direction_1, direction_2, direction_3;
  /// psi = 0.5 atan2(2 s_xz, s_zz - s_xx), degrees in (-90, 90]: angle of the in-plane major
  /// direction from vertical (+z), positive towards +x. 0 when the x-z sub-tensor is isotropic.
  double rotation_xz_deg;
  /// Same as rotation_xz_deg in the y-z plane, positive towards +y, degrees.
  double rotation_yz_deg;
  /// acos(|direction_1 . z|): tilt of the 3-D major direction from vertical, degrees in [0, 90].
  double tilt_deg;
};

/// Principal stresses of a symmetric stress tensor given tension positive (Pa).
/// Uses Eigen's SelfAdjointEigenSolver on s = -sigma.
/// Throws InputError if an entry is not finite, or if the tensor is not symmetric to within
/// 1e-8 of its largest entry (a measured tensor should be symmetrised before this call).
PrincipalStresses principal_stresses(const Mat3& stress_tension_positive);

}  // namespace dem::measure
