// How uniformly a simple-shear specimen shears, and the non-coaxiality of stress and strain rate,
// for the NGI simple-shear history (docs/model.md 8, 6.2, 6.3). Pure functions of numbers the
// caller gathers; nothing here reads a World.
//
// Geometry: the specimen lies between a bottom plate at z_bottom and a top plate at
// z_top = z_bottom + H (the plates' contact surfaces, at the same instant as the balls' heights).
// d is the horizontal unit shear direction. Over an interval the plates move U_bottom and U_top
// along d (the study moves the bottom and holds the top, U_top = 0, but any pair works), and a
// ball moves u along d. Uniform simple shear is the straight profile between the plates,
//   u_uniform(z) = U_bottom + (U_top - U_bottom) (z - z_bottom)/H,
// and its shear strain is gamma = (U_bottom - U_top)/H, the sign of docs/model.md 8 (positive for
// the bottom moving along +d under a held top). A shear band shows as a profile that is flat
// over most of the height and steep in a thin layer.
#pragma once

#include <dem/core/math.hpp>

#include <cstddef>
#include <vector>

namespace dem::measure {

/// Mean displacement of the balls in equal height bins between the plates. Bin i covers
/// [z_bottom + i h, z_bottom + (i + 1) h), h = H/bins, the top bin including z_top.
struct DisplacementProfile {
  std::vector<double> z_centre;           ///< centre of each bin, m
  std::vector<double> z_mean;             ///< mean height of the balls in the bin, m; NaN if empty
  std::vector<double> mean_displacement;  ///< mean u of the balls in the bin, m; NaN if empty
  std::vector<std::size_t> count;         ///< balls in the bin
};

/// Bins balls by height and averages their displacement increments.
/// z[b] is ball b's height (m), either at the interval's start or at its middle
/// ((z_start + z_end)/2); the choice is the caller's, and the middle is the better estimate
/// when balls cross bins during the interval (dilation, a long interval). u[b] is its
/// displacement increment along d over the interval (m). Balls outside [z_bottom, z_top] are
/// counted in the nearest end bin. Empty bins have count 0 and NaN means.
/// z_mean is returned because balls do not sit evenly in a bin: next to a plate their centres
/// stay at least a radius away from it, so an end bin's balls average well inside its centre.
/// shear_uniformity compares each mean with the uniform profile at z_mean, where a linear
/// field's bin mean is exact.
/// Throws InputError for bins < 1, z and u of different sizes, a non-finite z, u, z_bottom or
/// z_top, or z_top <= z_bottom.
DisplacementProfile displacement_profile(const std::vector<double>& z, const std::vector<double>& u, double z_bottom,
                                         double z_top, int bins);

/// Porosity of `bins` equal horizontal slabs between z_bottom and z_top (m) of a specimen of
/// cross-section `area` (m^2): 1 - (solid volume in the slab) / (area x slab height), each
/// sphere (centre height z[b], radius r[b]) split exactly between the slabs it crosses (the
/// volume of a sphere between two planes). The whole cross-section is one sample, so a slab of a
/// few ball diameters holds hundreds of balls and shows a density gradient that a measurement
/// sphere of a few tens of balls cannot. Overlaps are counted twice, as in the specimen porosity.
/// Throws InputError for bins < 1, z and r of different sizes, a non-finite z, a radius that is
/// not finite and > 0, area <= 0, or z_top <= z_bottom.
std::vector<double> porosity_profile(const std::vector<double>& z, const std::vector<double>& r, double z_bottom,
                                     double z_top, double area, int bins);

/// Result of shear_uniformity(). Strains are dimensionless, with the sign of gamma above: a
/// uniform field gives (U_bottom - U_top)/H in every third.
struct ShearUniformity {
  /// 1 - SS_res/SS_tot over the non-empty bins, each bin weighing the same:
  /// SS_res = sum_i (m_i - u_uniform(z_mean_i))^2, SS_tot = sum_i (m_i - mean_j m_j)^2, m_i the
  /// bin means. The model is the uniform profile set by the plates, not a fitted line, so R^2 is
  /// 1 for uniform shear, and can be negative for a banded field (a rigid block plus a thin band
  /// fits the plate-to-plate line worse than a constant does). NaN with fewer than 3 non-empty
  /// bins or when all bin means are equal (SS_tot = 0, e.g. an interval without motion).
  double r_squared;
  /// top_third_strain / bottom_third_strain. NaN if the bottom strain is exactly 0 (a bottom
  /// third that did not deform) or either strain is NaN.
  double top_bottom_strain_ratio;
  /// Shear strain of each third of the height: (u at its bottom - u at its top)/thickness,
  /// estimated as minus the least-squares slope du/dz of the bin means against z_mean over the
  /// bins whose centre lies in that third. NaN if the third has fewer than 2 non-empty bins
  /// (use bins >= 6, a multiple of 3 so that the thirds are alike).
  double top_third_strain;
  double middle_third_strain;
  double bottom_third_strain;
};

/// Uniformity measures of a displacement profile, given the plate heights (m) and the plates'
/// displacement increments along d over the same interval, u_bottom and u_top (m).
/// Throws InputError for a profile with fewer than 3 bins or vectors of different sizes, a
/// non-finite bin centre, or a non-empty bin with a non-finite mean; for non-finite plate
/// heights or displacements, or z_top <= z_bottom.
ShearUniformity shear_uniformity(const DisplacementProfile& profile, double z_bottom, double z_top, double u_bottom,
                                 double u_top);

/// Major-direction angle of a symmetric 2x2 tensor in the d-z plane, compression positive:
/// 0.5 atan2(2 s_dz, s_zz - s_dd), degrees in (-90, 90], from vertical (+z), positive towards +d
/// (the psi of docs/model.md 6.3). NaN if the tensor is isotropic (its deviator is zero to within
/// 1e-12 of its norm; the zero tensor included), since it then has no major direction, or if an
/// entry is not finite. Unlike PrincipalStresses::rotation_xz_deg, which reports 0 there for the
/// history's psi column, this never invents an angle.
double major_direction_deg(double s_dd, double s_zz, double s_dz);

/// Non-coaxiality: major direction of the stress minus major direction of the strain rate, each
/// from its d-z sub-tensor (s_dd = d.S.d, s_zz = S(2,2), s_dz = d.S.e_z of the symmetric part),
/// degrees wrapped into (-90, 90] (directions are axes: 89 and -89 are 2 degrees apart).
/// Both tensors are compression positive: negate the measurement sphere's stress and strain rate,
/// which are tension positive. Sign convention: with the bottom plate moving along +d under a
/// held top, u = U(1 - (z - z_bottom)/H), so the compression-positive strain rate has
/// e_dz = +gamma_dot/2 and its major direction is +45 degrees at constant volume and more than
/// 45 when the specimen dilates (e_zz < 0); the major stress tilts towards +d as well. A positive
/// result means the stress's major axis lies further towards +d than the strain rate's.
/// Returns NaN if either sub-tensor is isotropic or any entry of the inputs is NaN or infinite
/// (the sphere's strain rate is NaN when it holds too few balls: that is a NaN row, not an
/// error). Throws InputError for a finite d that is not a horizontal unit vector (to 1e-9).
double non_coaxiality_deg(const Mat3& stress_compression_positive, const Mat3& strain_rate_compression_positive,
                          const Vec3& d);

}  // namespace dem::measure
