#include "models/massspring/lattice.h"

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

namespace hcosim::models::massspring {
namespace {

[[noreturn]] void bad(const std::string& what) { throw std::invalid_argument("lattice: " + what); }

Lattice empty(int n, const Material& m) {
  if (!(m.mass > 0) || !(m.k >= 0) || !(m.b >= 0) || !(m.drag >= 0) || !std::isfinite(m.mass + m.k + m.b + m.drag))
    bad("material needs mass > 0 and finite k, b, drag >= 0");
  Lattice l;
  l.rest.setZero(3, n);
  l.mass.setConstant(n, m.mass);
  l.anchored.assign(n, 0);
  l.drag = m.drag;
  return l;
}

// A spring at rest in the lattice's rest configuration.
void connect(Lattice& l, int i, int j, const Material& m) {
  l.springs.push_back({i, j, (l.rest.col(i) - l.rest.col(j)).norm(), m.k, m.b});
}

void need(bool ok, const char* what) {
  if (!ok) bad(what);
}

}  // namespace

void check(const Lattice& l) {
  const int n = l.size();
  if (l.rest.cols() != n || int(l.anchored.size()) != n)
    bad("rest has " + std::to_string(l.rest.cols()) + " columns and anchored " + std::to_string(l.anchored.size()) +
        " entries for " + std::to_string(n) + " masses");
  if (!l.rest.allFinite()) bad("rest positions contain NaN or Inf");
  for (int i = 0; i < n; ++i)
    if (!(l.mass[i] > 0) || !std::isfinite(l.mass[i]))
      bad("mass " + std::to_string(i) + " is " + std::to_string(l.mass[i]) + " kg; it must be finite and > 0");
  if (!(l.drag >= 0) || !std::isfinite(l.drag)) bad("drag must be finite and >= 0");
  if (!l.gravity.allFinite()) bad("gravity contains NaN or Inf");
  for (std::size_t s = 0; s < l.springs.size(); ++s) {
    const Spring& sp = l.springs[s];
    const std::string name =
        "spring " + std::to_string(s) + " (" + std::to_string(sp.i) + "-" + std::to_string(sp.j) + ")";
    if (sp.i < 0 || sp.j < 0 || sp.i >= n || sp.j >= n) bad(name + " joins a mass outside 0.." + std::to_string(n - 1));
    if (sp.i == sp.j) bad(name + " joins a mass to itself");
    if (!(sp.rest >= 0) || !(sp.k >= 0) || !(sp.b >= 0) || !std::isfinite(sp.rest + sp.k + sp.b))
      bad(name + " needs finite rest, k, b >= 0");
  }
  for (std::size_t h = 0; h < l.quartets.size(); ++h) {
    const Quartet& e = l.quartets[h];
    const bool angle = e.measure == Measure::angle;
    const std::string name = std::string(angle ? "hinge " : "volume ") + std::to_string(h) + " (" +
                             std::to_string(e.i) + ", " + std::to_string(e.j) + ", " + std::to_string(e.k) + ", " +
                             std::to_string(e.l) + ")";
    const int c[4] = {e.i, e.j, e.k, e.l};
    for (int a = 0; a < 4; ++a) {
      if (c[a] < 0 || c[a] >= n) bad(name + " has a corner outside 0.." + std::to_string(n - 1));
      for (int b = 0; b < a; ++b)
        if (c[a] == c[b]) bad(name + " repeats a corner");
    }
    if (e.measure != Measure::angle && e.measure != Measure::volume) bad(name + " has an unknown measure");
    if (!(e.stiffness >= 0) || !(e.b >= 0) || !std::isfinite(e.stiffness + e.b))
      bad(name + " needs finite stiffness, b >= 0");
    if (angle && !(std::abs(e.rest) < M_PI)) bad(name + " needs a rest angle in (-pi, pi)");
    if (!angle && !(e.rest > 0 && std::isfinite(e.rest))) bad(name + " needs a finite rest volume > 0");
  }
}

Lattice make_sheet(int nx, int ny, double spacing, const Material& m) {
  need(nx >= 2 && ny >= 2, "a sheet needs at least 2 x 2 masses");
  need(spacing > 0 && std::isfinite(spacing), "spacing must be finite and > 0");
  Lattice l = empty(nx * ny, m);
  auto id = [nx](int i, int j) { return i + nx * j; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      l.rest.col(id(i, j)) << i * spacing, j * spacing, 0;
      l.anchored[id(i, j)] = i == 0 || j == 0 || i == nx - 1 || j == ny - 1;
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      if (i + 1 < nx) connect(l, id(i, j), id(i + 1, j), m);
      if (j + 1 < ny) connect(l, id(i, j), id(i, j + 1), m);
      if (i + 1 < nx && j + 1 < ny) {
        connect(l, id(i, j), id(i + 1, j + 1), m);
        connect(l, id(i + 1, j), id(i, j + 1), m);
      }
    }
  return l;
}

Lattice make_semisphere(int rings, int segments, double radius, const Material& m) {
  need(rings >= 1 && segments >= 3, "a semi-sphere needs at least 1 ring of 3 segments");
  need(radius > 0 && std::isfinite(radius), "radius must be finite and > 0");
  const int pole = rings * segments;
  Lattice l = empty(pole + 1, m);
  auto id = [segments](int r, int s) { return r * segments + (s % segments); };
  for (int r = 0; r < rings; ++r) {
    const double polar = M_PI / 2 * (1 - double(r) / rings);
    for (int s = 0; s < segments; ++s) {
      const double az = 2 * M_PI * s / segments;
      l.rest.col(id(r, s)) << radius * std::sin(polar) * std::cos(az), radius * std::sin(polar) * std::sin(az),
          radius * std::cos(polar);
      l.anchored[id(r, s)] = r == 0;
    }
  }
  l.rest.col(pole) << 0, 0, radius;
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      connect(l, id(r, s), id(r, s + 1), m);
      if (r + 1 < rings) {
        connect(l, id(r, s), id(r + 1, s), m);
        connect(l, id(r, s), id(r + 1, s + 1), m);
      } else {
        connect(l, id(r, s), pole, m);
      }
    }
  return l;
}

Lattice make_shell(const Eigen::Matrix3Xd& vertices, const std::vector<Eigen::Vector3i>& triangles, const Material& m) {
  need(vertices.allFinite(), "a shell's vertices must be finite");
  Lattice l = empty(int(vertices.cols()), m);
  l.rest = vertices;
  std::set<std::pair<int, int>> edges;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Eigen::Vector3i& c = triangles[t];
    for (int q = 0; q < 3; ++q) {
      if (c[q] < 0 || c[q] >= l.size() || c[q] == c[(q + 1) % 3])
        bad("shell: triangle " + std::to_string(t) + " has a corner out of range or repeated");
      edges.emplace(std::min(c[q], c[(q + 1) % 3]), std::max(c[q], c[(q + 1) % 3]));
    }
  }
  for (const auto& [i, j] : edges) connect(l, i, j, m);
  return l;
}

Lattice make_box(int nx, int ny, int nz, double spacing, const Material& m, Shear shear) {
  need(nx >= 2 && ny >= 2 && nz >= 2, "a box needs at least 2 x 2 x 2 masses");
  need(spacing > 0 && std::isfinite(spacing), "spacing must be finite and > 0");
  Lattice l = empty(nx * ny * nz, m);
  auto id = [nx, ny](int i, int j, int k) { return i + nx * (j + ny * k); };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) l.rest.col(id(i, j, k)) << i * spacing, j * spacing, k * spacing;
  // One face square with corners a, a+u, a+v, a+u+v: its diagonal(s).
  auto face = [&](int a, int u, int v, int parity) {
    if (shear == Shear::both || parity % 2 == 0) connect(l, a, a + u + v, m);
    if (shear == Shear::both || parity % 2 == 1) connect(l, a + u, a + v, m);
  };
  const int dx = 1, dy = nx, dz = nx * ny;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int a = id(i, j, k), p = i + j + k;
        if (i + 1 < nx) connect(l, a, a + dx, m);
        if (j + 1 < ny) connect(l, a, a + dy, m);
        if (k + 1 < nz) connect(l, a, a + dz, m);
        if (i + 1 < nx && j + 1 < ny) face(a, dx, dy, p);
        if (i + 1 < nx && k + 1 < nz) face(a, dx, dz, p);
        if (j + 1 < ny && k + 1 < nz) face(a, dy, dz, p);
      }
  return l;
}

}  // namespace hcosim::models::massspring
