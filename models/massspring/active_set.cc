#include "models/massspring/simulator_impl.h"

#include <algorithm>

namespace hcosim::models::massspring {

void Simulator::Impl::enter(int i) {
  if (lat.anchored[i]) return;
  slot[i] = int(masses.size()), masses.push_back(i);
  ++moved;
  for (int e = adj.start[i]; e < adj.start[i + 1]; ++e) {
    const int si = adj.spring[e];
    if (ends[si]++ == 0) spring_slot[si] = int(springs.size()), springs.push_back(si);
  }
  for (int e = quartet_index.start[i]; e < quartet_index.start[i + 1]; ++e) {
    const int qi = quartet_index.quartet[e];
    if (corners[qi]++ == 0) quartet_slot[qi] = int(quartets.size()), quartets.push_back(qi);
  }
}

void Simulator::Impl::leave(int i, State& s) {
  if (slot[i] < 0) return;
  remove(i);
  s.v.col(i).setZero();
}

void Simulator::Impl::remove(int i) {
  const int k = slot[i];
  masses[k] = masses.back(), slot[masses[k]] = k, masses.pop_back();
  ++moved;
  slot[i] = -1;
  for (int e = adj.start[i]; e < adj.start[i + 1]; ++e) {
    const int si = adj.spring[e];
    if (--ends[si] > 0) continue;
    const int q = spring_slot[si];
    springs[q] = springs.back(), spring_slot[springs[q]] = q, springs.pop_back();
    spring_slot[si] = -1;
  }
  for (int e = quartet_index.start[i]; e < quartet_index.start[i + 1]; ++e) {
    const int qi = quartet_index.quartet[e];
    if (--corners[qi] > 0) continue;
    const int q = quartet_slot[qi];
    quartets[q] = quartets.back(), quartet_slot[quartets[q]] = q, quartets.pop_back();
    quartet_slot[qi] = -1;
  }
}

void Simulator::Impl::hold(int i, bool on) {
  if (held[i] == on) return;
  held[i] = on;
  lat.anchored[i] = on;
  inv_mass[i] = on ? 0 : 1 / lat.mass[i];
  if (on) {
    if (slot[i] >= 0) remove(i);
    if (adaptive && !active[i]) activate(i);
  } else if (!adaptive || cover[i] > 0) {
    enter(i);
  }
}

void Simulator::Impl::activate(int i) {
  active[i] = 1;
  if (cover[i]++ == 0) enter(i);
  for (int e = adj.start[i]; e < adj.start[i + 1]; ++e)
    if (cover[adj.other[e]]++ == 0) enter(adj.other[e]);
}

void Simulator::Impl::deactivate(int i, State& s) {
  active[i] = 0;
  if (--cover[i] == 0) leave(i, s);
  for (int e = adj.start[i]; e < adj.start[i + 1]; ++e)
    if (--cover[adj.other[e]] == 0) leave(adj.other[e], s);
}

void Simulator::Impl::select(State& s, const std::vector<PointForce>& in) {
  if (adaptive) {
    if (s.quiet != seen_quiet) {
      leave_all();
      std::fill(active.begin(), active.end(), 0);
      std::fill(cover.begin(), cover.end(), 0);
      for (int i = 0; i < lat.size(); ++i)
        if (held[i] || (!lat.anchored[i] && s.quiet[i] < opt.retire_steps)) activate(i);
      seen_quiet = s.quiet;
    }
    for (const PointForce& p : in)
      if (!lat.anchored[p.mass] && p.force.squaredNorm() > 0) {
        s.quiet[p.mass] = seen_quiet[p.mass] = 0;
        if (!active[p.mass]) activate(p.mass);
      }
  }
  // Entering and leaving scatter the lists; back in lattice order once an
  // eighth of them moved, so that the force loop walks memory forward.
  if (moved * 8 > masses.size()) sort_lists();
  loads.clear();
  for (const PointForce& p : in)
    if (slot[p.mass] >= 0) loads.push_back(p);
}

void Simulator::Impl::sort_lists() {
  std::sort(masses.begin(), masses.end());
  std::sort(springs.begin(), springs.end());
  std::sort(quartets.begin(), quartets.end());
  for (int k = 0; k < int(masses.size()); ++k) slot[masses[k]] = k;
  for (int k = 0; k < int(springs.size()); ++k) spring_slot[springs[k]] = k;
  for (int k = 0; k < int(quartets.size()); ++k) quartet_slot[quartets[k]] = k;
  moved = 0;
}

void Simulator::Impl::leave_all() {
  for (const int i : masses) slot[i] = -1;
  for (const int si : springs) spring_slot[si] = -1, ends[si] = 0;
  for (const int qi : quartets) quartet_slot[qi] = -1, corners[qi] = 0;
  masses.clear(), springs.clear(), quartets.clear();
}

void Simulator::Impl::back_up(const State& s) {
  whole = 2 * masses.size() > std::size_t(lat.size());
  backed.clear();
  if (whole) {
    bx = s.x, bv = s.v;
    return;
  }
  bx.resize(3, masses.size()), bv.resize(3, masses.size());
  for (const int i : masses) back_up(i, s);
}

void Simulator::Impl::back_up(int i, const State& s) {
  if (whole) return;
  const int k = int(backed.size());
  if (k >= bx.cols()) bx.conservativeResize(3, 2 * k + 1), bv.conservativeResize(3, 2 * k + 1);
  bx.col(k) = s.x.col(i), bv.col(k) = s.v.col(i);
  backed.push_back(i);
}

void Simulator::Impl::restore(State& s) const {
  if (whole) {
    s.x = bx, s.v = bv;
    return;
  }
  for (std::size_t k = 0; k < backed.size(); ++k) s.x.col(backed[k]) = bx.col(k), s.v.col(backed[k]) = bv.col(k);
}

bool Simulator::Impl::grow(State& s) {
  grown.clear();
  for (const int i : masses)
    if (!active[i] && 0.5 * lat.mass[i] * s.v.col(i).squaredNorm() > opt.threshold) grown.push_back(i);
  const std::size_t before = masses.size();
  for (const int i : grown) {
    s.quiet[i] = seen_quiet[i] = 0;
    activate(i);
  }
  for (std::size_t k = before; k < masses.size(); ++k) back_up(masses[k], s);
  // The last force pass left the entering springs' energies stale.
  if (!grown.empty()) elastic_fresh = false;
  return !grown.empty();
}

int Simulator::Impl::retire(State& s) {
  if (!elastic_fresh) spring_energy(s.x);
  std::vector<int> on, off;
  int count = 0;
  for (const int i : masses) {
    const double e = 0.5 * lat.mass[i] * s.v.col(i).squaredNorm() + elastic[i];
    int& q = s.quiet[i];
    if (e > opt.threshold) {
      q = 0;
      if (!active[i]) on.push_back(i);
    } else if (q < opt.retire_steps && ++q == opt.retire_steps && active[i]) {
      off.push_back(i);
    }
    seen_quiet[i] = q;
    count += q < opt.retire_steps;
  }
  for (const int i : on) activate(i);
  for (const int i : off) deactivate(i, s);
  return count;
}

}  // namespace hcosim::models::massspring
