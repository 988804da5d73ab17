// A periodic cell: a parallelepiped that space is tiled with, so that a specimen has no walls
// (docs/model.md 13).
// Its edge vectors are the columns of the cell matrix h (m), from the corner `origin`; a point x
// has reduced coordinates s = h^-1 (x - origin), in [0, 1) on every axis inside the cell. The
// cell deforms with a velocity gradient L (1/s): h' = L h, integrated by the World every step
// (World::set_velocity_gradient), so a homogeneous strain is imposed by the cell and the
// particles follow it through their contacts.
//
// A particle's image across the cell's faces is the particle moved by an integer image vector n of
// whole cells: x + h n, moving at v + L h n (the Lees-Edwards shift of a deforming cell: the
// image lives in the next cell, which the mean flow carries along). A contact between a particle
// and another's image carries n (core/pair_geometry.hpp, PairContacts::image).
//
// The image vectors a contact can have are those with components -1, 0 and 1, packed into one byte
// (image_code): while the cell is at least three search cells wide (the World refuses a smaller
// one), a particle touches at most one image of another, and only one in a neighbouring cell.
//
// A cell sheared far is re-mapped to an equivalent, less skewed one (LAMMPS's flip, YADE's
// flipCell): an edge is replaced by itself minus a whole multiple of another, h' = h M with M an
// integer matrix of determinant 1, which tiles space with the same images. The World does it at a
// rebuild (remap_tilt), where the particles are wrapped into the new cell and every contact's
// image is found again, so no contact loses its history and no force jumps.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include <dem/base/math.hpp>

namespace dem {

/// An image vector n, components in {-1, 0, 1}, packed as (n0 + 1) + 3 (n1 + 1) + 9 (n2 + 1).
using ImageCode = std::uint8_t;
inline constexpr int image_count = 27;
inline constexpr ImageCode home_image = 13;  // n = 0: the particle itself
constexpr ImageCode image_code(int n0, int n1, int n2) {
  return static_cast<ImageCode>((n0 + 1) + 3 * (n1 + 1) + 9 * (n2 + 1));
}
/// The image vector of `code`.
constexpr std::array<int, 3> image_vector(ImageCode code) { return {code % 3 - 1, code / 3 % 3 - 1, code / 9 - 1}; }
/// -n: the image of piece 1 as seen from piece 2, when a contact's pieces trade places.
constexpr ImageCode opposite_image(ImageCode code) { return static_cast<ImageCode>(image_count - 1 - code); }

/// Each image code's position shift h n (m) and velocity shift L h n (m/s), for a cell as it is
/// now: the contact loops look a contact's shift up here by its code (one load per contact).
struct ImageShifts {
  std::array<Vec3, image_count> position;  // m
  std::array<Vec3, image_count> velocity;  // m/s
};

class PeriodicCell {
 public:
  /// A cell with edge vectors the columns of `h` (m) from `origin` (m), at rest (L = 0).
  /// InputError unless h is finite with a positive determinant (right-handed, not flat).
  explicit PeriodicCell(const Mat3& h = Mat3::Identity(), const Vec3& origin = Vec3::Zero());
  /// An axis-aligned box from `low` to `high` (m).
  static PeriodicCell box(const Vec3& low, const Vec3& high);

  const Mat3& matrix() const { return h_; }          // m, edge vectors as columns
  const Mat3& inverse() const { return h_inverse_; }  // 1/m
  const Vec3& origin() const { return origin_; }      // m
  Vec3 edge(int axis) const { return h_.col(axis); }  // m
  /// det h (m^3).
  double volume() const { return h_.determinant(); }
  /// The distance between each pair of opposite faces (m): the cell's thickness across axis a,
  /// volume / |h_b x h_c|. The neighbour search needs it, not the edge lengths, in a skewed cell.
  Vec3 widths() const;
  /// Replaces the cell matrix (a controller, a restart). Checked as in the constructor.
  void set_matrix(const Mat3& h);

  /// The velocity gradient the cell deforms with (1/s): h' = L h. Its symmetric part is the
  /// strain rate, its antisymmetric part the spin.
  const Mat3& velocity_gradient() const { return velocity_gradient_; }
  void set_velocity_gradient(const Mat3& velocity_gradient);
  /// One step of h' = L h for a constant L: h <- exp(dt L) h, the exponential to fourth order in
  /// dt L (an error of order (dt |L|)^5 a step), so that a traceless L keeps the volume to
  /// rounding over millions of steps (a first-order step drifts by (dt |L|)^2 a step). `dt` in s.
  void advance(double dt);

  /// Which axes are periodic. Only all three is supported for now (World::set_periodic_cell
  /// refuses others, saying so); the flags keep a place for a cell between walls.
  const std::array<bool, 3>& periodic_axes() const { return periodic_; }
  void set_periodic_axes(const std::array<bool, 3>& periodic) { periodic_ = periodic; }

  /// Reduced coordinates s = h^-1 (x - origin) of a point x (m).
  Vec3 reduced(const Vec3& x) const { return h_inverse_ * (x - origin_); }
  /// The whole cells m (floor of s on each periodic axis) that `x` lies beyond the home cell:
  /// x - h m is inside it (up to rounding at the faces).
  std::array<int, 3> cells_out(const Vec3& x) const;
  /// The home-cell position of `x` (m): x - h m with m = cells_out(x).
  Vec3 wrapped(const Vec3& x) const;

  /// h n (m), the position shift of image n.
  Vec3 image_shift(const std::array<int, 3>& n) const;
  /// L h n (m/s), the velocity shift of image n (Lees-Edwards).
  Vec3 image_velocity_shift(const std::array<int, 3>& n) const;
  /// Both, for every image code (ImageShifts).
  ImageShifts image_shifts() const;
  /// The mean-field velocity L (x - origin) at x (m/s): the velocity of the affine deformation.
  Vec3 affine_velocity(const Vec3& x) const { return velocity_gradient_ * (x - origin_); }

  /// Re-maps a cell whose tilt factors exceed `tilt_limit` (LAMMPS's, in the frame of the cell's
  /// own Gram-Schmidt axes: the first edge's component of the second along it, and the third's
  /// along the first two, each divided by that edge's length there) by whole edges, each factor
  /// then at most 1/2 in size. The limit is above 1/2 so that a shear reversing near 1/2 does not
  /// re-map back and forth. Returns true if h changed. Only when tilt_remap() is on.
  bool remap_tilt(double tilt_limit = 0.6);
  /// Whether the World re-maps a skewed cell at its rebuilds (default on; off for comparisons with
  /// codes that do not, such as LAMMPS's fix deform with flip no).
  bool tilt_remap() const { return tilt_remap_; }
  void set_tilt_remap(bool remap) { tilt_remap_ = remap; }

  /// The largest distance (m) any image shift h n (|n_a| <= 1) has moved since the cell was `then`:
  /// the sum of the edges' displacements, which bounds how far a contact's image has moved.
  double image_travel_since(const Mat3& then) const;

 private:
  Mat3 h_;
  Mat3 h_inverse_;
  Vec3 origin_;
  Mat3 velocity_gradient_ = Mat3::Zero();
  std::array<bool, 3> periodic_{true, true, true};
  bool tilt_remap_ = true;
};

/// "x y z", the names of the axes flagged in `axes` (for messages).
std::string axis_names(const std::array<bool, 3>& axes);

}  // namespace dem
