// The S-Chain haptic model (001 §II.A, eq 1; Park et al. 2002, Kim, Park
// and Kwon 2005), a shape-retaining descendant of 3D ChainMail (Gibson
// 1997): chain elements on a voxel lattice, each linked to its 6
// neighbours. A link allows the two displacements to differ by at most
// `stretch` or `compress` times the spacing along the link and `shear`
// across it; a smaller range is a stiffer chain. The contacted element
// follows the haptic point, violations propagate outward breadth first,
// each element moving at most once, until none remain, and every element
// relaxes back toward rest, so nothing is left displaced after release.
// The force on the stylus is F = -sum_i K_i d(i) over the moved chains.
// Cost grows with the number of moved chains, not the lattice size.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace hcosim::models::deformable {

// Per element: its spring coefficient and the fractions of the spacing
// its links allow. A link between two elements takes the tighter of their
// ranges.
struct ChainMaterial {
  double stiffness = 2;    // K_i, N/m (a 10^3 cube pressed 5 mm pushes back about 1.7 N)
  double stretch = 0.05;   // along the link, apart
  double compress = 0.05;  // along the link, together
  double shear = 0.05;     // across the link
};

struct ChainLattice {
  int nx = 0, ny = 0, nz = 0;
  double spacing = 0.01;                             // m
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // element (0, 0, 0), world frame, m
  std::vector<ChainMaterial> material;               // one per element, index i + nx (j + ny k)
  std::vector<std::uint8_t> anchored;                // 1: never moves
  std::vector<std::uint8_t> present;                 // 0: no element there (a body that is not a box), no links

  int size() const { return nx * ny * nz; }
  int index(int i, int j, int k) const { return i + nx * (j + ny * k); }
  Eigen::Vector3d rest(int e) const;
};

// nx x ny x nz elements of one material, all present, none anchored. Throws
// std::invalid_argument for fewer than 2 per side, a non-positive spacing
// or stiffness, or ranges outside (0, 1).
ChainLattice make_chain_box(int nx, int ny, int nz, double spacing, const ChainMaterial& m);

class SChain {
 public:
  // relax_rate: 1/s, how fast displaced elements return toward rest
  // (their displacement decays as e^(-rate t) where constraints allow).
  // limit_stiffness: N/m, how hard the object pushes back on a haptic point
  // pressed past where the anchors let the contacted element go (a chain
  // fully compressed against its anchors is rigid; this renders it as a
  // stiff wall the device can display).
  explicit SChain(ChainLattice lattice, double relax_rate = 50, double limit_stiffness = 1000);

  // One haptic tick of dt seconds. With `contact` >= 0 that element is held
  // at `target` (world frame, m), or as near it as the anchors allow; with
  // -1 nothing is touched. Returns the number of elements the propagation
  // visited this tick. Throws
  // std::invalid_argument for a bad element, a non-finite target or dt.
  int tick(double dt, int contact, const Eigen::Vector3d& target);

  // F = -sum K_i d(i) - limit_stiffness * gap (N, world frame): the force
  // on the stylus; gap is how far the target lies past the contacted element.
  Eigen::Vector3d force() const;

  const Eigen::Vector3d& displacement(int e) const { return u_[e]; }
  const std::vector<int>& moved() const { return moved_; }  // elements displaced from rest
  const ChainLattice& lattice() const { return lat_; }
  const std::vector<int>& surface() const { return surface_; }  // the surface elements (below)

  // The surface element (one present with a neighbour missing or on the
  // grid's border) nearest to p (world frame), or -1 if p is farther than
  // one spacing outside the lattice's box.
  int nearest_surface(const Eigen::Vector3d& p) const;

 private:
  // Moves neighbour n of `from` (link along `axis`, side +1 or -1)
  // minimally into its allowed box, remembering its old value; true if it
  // moved. An anchored n that would have to move sets *blocked instead.
  bool enforce(int from, int n, int axis, int side, bool* blocked);
  // Puts the contact at displacement u and propagates; false if an anchor
  // blocked it. *count: elements visited.
  bool propagate(int contact, const Eigen::Vector3d& u, int* count);
  void undo();  // restores what the last propagate() moved
  void mark(int e);

  ChainLattice lat_;
  double relax_rate_, limit_stiffness_;
  Eigen::Vector3d gap_ = Eigen::Vector3d::Zero();  // m, target minus where the contact could go
  std::vector<Eigen::Vector3d> u_;                 // displacement from rest, m
  std::vector<int> moved_;                         // elements with u != 0
  std::vector<std::uint8_t> in_moved_;             // 1 while in moved_
  std::vector<std::uint8_t> on_surface_;           // 1: a surface element
  std::vector<int> surface_;                       // the surface elements
  std::vector<std::uint32_t> visit_;               // stamp of the last propagation that reached it
  std::vector<std::uint8_t> queued_;               // 1 while waiting in queue_
  std::uint32_t stamp_ = 0;
  std::vector<int> queue_;
  std::vector<std::pair<int, Eigen::Vector3d>> undo_;
};

}  // namespace hcosim::models::deformable
