// Contact fabric: rose histograms of contact normals in a plane, their second-order Fourier fits
// (Rothenburg and Bathurst 1989, docs/model.md 9.2), and the 3-D fabric tensor (docs/model.md 9.3).
//
// A contact normal n and -n describe the same contact, so projected angles are folded into
// [0, 180) degrees; the full-circle rose is drawn by symmetry. The fit is done twice: from the
// binned histogram with an FFT and a sinc correction for the bin width (what a rose plot shows),
// and bin-free from the raw angles (the reference, which has no binning error).
//
// Threading: rose() creates and destroys an FFTW plan in the calling thread. FFTW's planner is
// not thread safe, so do not call rose() from several threads at once (e.g. inside an OpenMP
// loop), nor while another thread plans FFTW transforms, unless the program has called
// fftw_make_planner_thread_safe(). fabric_tensor() has no such restriction.
#pragma once

#include <dem/core/math.hpp>

#include <vector>

namespace dem::measure {

/// Plane onto which contact normals are projected; theta = atan2(second, first), folded to
/// [0, 180) degrees. ShearXZ: (x, z), the study's front view. HorizontalXY: (x, y). SideYZ: (y, z).
enum class RosePlane { ShearXZ, HorizontalXY, SideYZ };

/// One contact for fabric statistics.
struct ContactSample {
  Vec3 normal;          ///< unit contact normal, either sign (|n| = 1 within 1e-6)
  double normal_force;  ///< N, compression positive; any finite value is accepted
};

/// Rose histogram of projected contact normals with its Fourier fits.
/// Bins are [bin_lo_deg[m], bin_lo_deg[m] + bin_width_deg). Angles are degrees in [0, 180).
struct Rose {
  RosePlane plane;
  double bin_width_deg;                   ///< degrees
  std::vector<double> bin_lo_deg;         ///< lower bin edges, degrees
  std::vector<long> count;                ///< contacts per bin
  std::vector<double> fraction;           ///< count / contacts_used
  std::vector<double> mean_normal_force;  ///< N, mean F_n per bin; 0 for empty bins
  // Second-order Fourier fits from the binned data, FFT plus sinc correction (docs/model.md 9.2):
  // E(theta) = (1/pi)(1 + a cos 2(theta - theta_a)), f_n(theta) = f0 (1 + a_n cos 2(theta - theta_n)).
  double a;            ///< contact-normal anisotropy, -
  double theta_a_deg;  ///< its principal direction, degrees
  double f0;           ///< N, unweighted mean of the bin averages (empty bins count as 0)
  double a_n;          ///< normal-force anisotropy, -
  double theta_n_deg;  ///< its principal direction, degrees
  // Bin-free equivalents from the raw angles:
  double a_direct;            ///< (2/N) |sum exp(2 i theta_c)|, -
  double theta_a_direct_deg;  ///< 0.5 arg(sum exp(2 i theta_c)), degrees
  double mean_force_all;      ///< N, mean F_n over all used contacts (Rothenburg-Bathurst f0)
  long contacts_used;         ///< contacts counted in the rose
  long contacts_skipped;      ///< contacts normal to the plane (projected length < 1e-6)
};

/// Rose of the contact normals projected onto `plane`, with bins of bin_width_deg degrees.
/// Contacts whose projected normal is shorter than 1e-6 (nearly perpendicular to the plane)
/// have no defined angle and are skipped and counted in contacts_skipped.
/// If no contact is used, counts are zero and every fit and mean is NaN.
/// Throws InputError if bin_width_deg does not divide 180 into at least 3 bins (a second-order
/// fit needs 3), or if a normal is not a finite unit vector or a force is not finite.
/// Not thread safe: see the note at the top of this header.
Rose rose(const std::vector<ContactSample>& contacts, RosePlane plane, double bin_width_deg = 10.0);

/// How far a rose is from mirror symmetry about 90 degrees (the vertical, in the x-z and y-z
/// planes): the left-right asymmetry the study reads in its 4D roses. Each bin [lo, lo + w) is set
/// against its mirror [180 - lo - w, 180 - lo):
///   count = sum over pairs |c - c_mirror| / sum of c         (0: symmetric, 1: one side only)
///   force = sum over pairs |f - f_mirror| / sum of f         (f: the bins' mean normal force)
/// and the tilts of the Fourier principal directions from the vertical (90 - theta, degrees in
/// (-90, 90]; positive towards the plane's first axis, +x in x-z). NaN where the rose has no contact.
struct RoseAsymmetry {
  double count, force;                   // -
  double count_tilt_deg, force_tilt_deg; // degrees
};
RoseAsymmetry rose_asymmetry(const Rose& rose);

/// Fabric tensor phi_ij = (1/N) sum_c n_i n_j (dimensionless, symmetric, trace 1).
/// Throws InputError for an empty sample or a normal that is not a finite unit vector.
Mat3 fabric_tensor(const std::vector<ContactSample>& contacts);

}  // namespace dem::measure
