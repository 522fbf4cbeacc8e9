#include "adapters/reference/calculix.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace hcosim::adapters::reference {
namespace {

void need(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("calculix: " + what);
}

int nodes_of(const std::string& element) {
  if (element == "C3D8") return 8;
  if (element == "C3D20") return 20;
  throw std::invalid_argument("calculix: element '" + element + "' is not C3D8 or C3D20");
}

// A hexahedron's corners, then (C3D20) its edges' midpoints, as offsets on
// a lattice of two steps per element: CalculiX's node order.
const std::array<std::array<int, 3>, 20>& hex_offsets() {
  static const std::array<std::array<int, 3>, 20> o = [] {
    const std::array<std::array<int, 3>, 8> c{
        {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 2}, {2, 0, 2}, {2, 2, 2}, {0, 2, 2}}};
    const std::array<std::array<int, 2>, 12> edges{
        {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}}};
    std::array<std::array<int, 3>, 20> out{};
    for (int i = 0; i < 8; ++i) out[i] = c[i];
    for (int e = 0; e < 12; ++e)
      for (int d = 0; d < 3; ++d) out[8 + e][d] = (c[edges[e][0]][d] + c[edges[e][1]][d]) / 2;
    return out;
  }();
  return o;
}

// Numbers written 16 to a line, as CalculiX's lists take them.
void write_list(std::ostream& out, const std::vector<int>& ids) {
  for (std::size_t i = 0; i < ids.size(); ++i)
    out << ids[i] + 1 << (i + 1 == ids.size() ? "\n" : (i % 16 == 15 ? ",\n" : ", "));
}

std::string tail(const std::string& path, int lines) {
  std::ifstream in(path);
  std::vector<std::string> all;
  for (std::string l; std::getline(in, l);) all.push_back(l);
  std::string out;
  for (std::size_t i = all.size() > std::size_t(lines) ? all.size() - lines : 0; i < all.size(); ++i)
    out += all[i] + "\n";
  return out;
}

}  // namespace

Job box(const Eigen::Vector3d& size, const std::array<int, 3>& n, const std::string& element) {
  need((size.array() > 0).all() && size.allFinite(), "a box's size must be > 0");
  need(n[0] >= 1 && n[1] >= 1 && n[2] >= 1, "a box needs at least one element along each axis");
  const bool quadratic = nodes_of(element) == 20;
  Job job;
  job.element = element;
  // Lattice points two steps an element; a C3D8 uses the even ones, a
  // C3D20 those with at most one odd coordinate (no face or body centres).
  const std::array<int, 3> m{2 * n[0] + 1, 2 * n[1] + 1, 2 * n[2] + 1};
  std::vector<int> id(std::size_t(m[0]) * m[1] * m[2], -1);
  const auto at = [&](int i, int j, int k) -> int& { return id[(std::size_t(k) * m[1] + j) * m[0] + i]; };
  for (int k = 0; k < m[2]; ++k)
    for (int j = 0; j < m[1]; ++j)
      for (int i = 0; i < m[0]; ++i) {
        const int odd = i % 2 + j % 2 + k % 2;
        if (quadratic ? odd > 1 : odd > 0) continue;
        at(i, j, k) = int(job.nodes.size());
        job.nodes.emplace_back(size.x() * i / (m[0] - 1), size.y() * j / (m[1] - 1), size.z() * k / (m[2] - 1));
        const std::array<int, 3> p{i, j, k};
        const char* axis[] = {"X", "Y", "Z"};
        for (int d = 0; d < 3; ++d) {
          if (p[d] == 0) job.sets[std::string(axis[d]) + "MIN"].push_back(at(i, j, k));
          if (p[d] == m[d] - 1) job.sets[std::string(axis[d]) + "MAX"].push_back(at(i, j, k));
        }
      }
  const int count = quadratic ? 20 : 8;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        std::vector<int> e;
        for (int c = 0; c < count; ++c) {
          const auto& o = hex_offsets()[c];
          e.push_back(at(2 * i + o[0], 2 * j + o[1], 2 * k + o[2]));
        }
        job.elements.push_back(std::move(e));
      }
  return job;
}

std::string input_file(const Job& job) {
  const Material& mat = job.material;
  need(mat.young > 0 && std::isfinite(mat.young), "Young's modulus must be finite and > 0");
  need(mat.poisson >= 0 && mat.poisson < 0.5, "Poisson's ratio must be in [0, 0.5)");
  const int count = nodes_of(job.element);
  need(!job.elements.empty(), "the job has no element");
  const int n = int(job.nodes.size());
  std::ostringstream out;
  out.precision(12);  // CalculiX reads at most 20 characters a field
  out << "** hcosim: a reference job (adapters/reference/calculix.h)\n*NODE, NSET=NALL\n";
  for (int i = 0; i < n; ++i) {
    need(job.nodes[i].allFinite(), "node " + std::to_string(i) + " is not finite");
    out << i + 1 << ", " << job.nodes[i].x() << ", " << job.nodes[i].y() << ", " << job.nodes[i].z() << "\n";
  }
  out << "*ELEMENT, TYPE=" << job.element << ", ELSET=EALL\n";
  for (std::size_t e = 0; e < job.elements.size(); ++e) {
    const std::vector<int>& nodes = job.elements[e];
    need(int(nodes.size()) == count, "element " + std::to_string(e) + " has " + std::to_string(nodes.size()) +
                                         " nodes; " + job.element + " has " + std::to_string(count));
    out << e + 1;
    for (int c = 0; c < count; ++c) {
      need(nodes[c] >= 0 && nodes[c] < n, "element " + std::to_string(e) + " names a node out of range");
      out << (c == 10 ? ",\n" : ", ") << nodes[c] + 1;
    }
    out << "\n";
  }
  for (const auto& [name, ids] : job.sets) {
    need(std::regex_match(name, std::regex("[A-Z][A-Z0-9_]{0,39}")), "set name '" + name + "' is not A-Z, 0-9, _");
    need(!ids.empty(), "set " + name + " is empty");
    for (int i : ids) need(i >= 0 && i < n, "set " + name + " names a node out of range");
    out << "*NSET, NSET=" << name << "\n";
    write_list(out, ids);
  }
  out << "*MATERIAL, NAME=TISSUE\n";
  if (mat.law == Law::linear) {
    out << "*ELASTIC\n" << mat.young << ", " << mat.poisson << "\n";
  } else {
    const double shear = mat.young / (2 * (1 + mat.poisson)), bulk = mat.young / (3 * (1 - 2 * mat.poisson));
    out << "*HYPERELASTIC, NEO HOOKE\n" << shear / 2 << ", " << 2 / bulk << "\n";
  }
  out << "*SOLID SECTION, ELSET=EALL, MATERIAL=TISSUE\n";
  out << "*STEP" << (job.nlgeom ? ", NLGEOM" : "") << ", INC=1000\n*STATIC\n0.1, 1.0, 1e-6, 0.25\n";
  out << "*BOUNDARY\n";
  for (const Fix& f : job.fixes) {
    need(job.sets.count(f.set), "a fix names set " + f.set + ", which the job lacks");
    need(f.dof >= 1 && f.dof <= 3 && std::isfinite(f.value), "a fix of set " + f.set + " is not dof 1..3 or finite");
    out << f.set << ", " << f.dof << ", " << f.dof << ", " << f.value << "\n";
  }
  if (!job.loads.empty()) out << "*CLOAD\n";
  for (const Load& l : job.loads) {
    need(job.sets.count(l.set), "a load names set " + l.set + ", which the job lacks");
    need(l.dof >= 1 && l.dof <= 3 && std::isfinite(l.value), "a load on set " + l.set + " is not dof 1..3 or finite");
    const std::vector<int>& ids = job.sets.at(l.set);
    for (int i : ids) out << i + 1 << ", " << l.dof << ", " << l.value / double(ids.size()) << "\n";
  }
  for (const std::string& s : job.reactions) {
    need(job.sets.count(s), "a reaction names set " + s + ", which the job lacks");
    out << "*NODE PRINT, NSET=" << s << ", TOTALS=ONLY\nRF\n";
  }
  out << "*NODE PRINT, NSET=NALL\nU\n*END STEP\n";
  return out.str();
}

bool ccx_available() { return std::system("command -v ccx >/dev/null 2>&1") == 0; }

Result run(const Job& job, const std::string& dir) {
  namespace fs = std::filesystem;
  need(dir.find('\'') == std::string::npos, "the folder '" + dir + "' has a quote, which the shell would split");
  fs::create_directories(dir);
  const fs::path inp = fs::path(dir) / "job.inp", log = fs::path(dir) / "job.log", dat = fs::path(dir) / "job.dat";
  std::ofstream(inp) << input_file(job);
  fs::remove(dat);
  if (!ccx_available())
    throw std::runtime_error("calculix: no ccx on PATH (Debian's calculix-ccx; deploy/setup.sh installs it)");
  // One thread: the reference is run beside the tests, and its answer
  // does not depend on it.
  const std::string command =
      "cd '" + dir + "' && OMP_NUM_THREADS=1 CCX_NPROC_EQUATION_SOLVER=1 ccx -i job >job.log 2>&1";
  const int status = std::system(command.c_str());
  const std::string said = tail(log.string(), 12);
  if (status != 0 || said.find("Job finished") == std::string::npos)
    throw std::runtime_error("calculix: ccx failed on " + inp.string() + ":\n" + said);

  // The .dat holds a block per increment for each print: a header line,
  // a blank line, then rows. The last block of each is the result.
  Result r;
  r.displacement.assign(job.nodes.size(), Eigen::Vector3d::Constant(NAN));
  const std::regex total(R"(\s*total force \(fx,fy,fz\) for set (\S+) and time.*)");
  const std::regex displacements(R"(\s*displacements \(vx,vy,vz\) for set (\S+) and time.*)");
  std::ifstream in(dat);
  // "", the set whose total is read, or "*U" (no set's name: they are A-Z, 0-9, _).
  std::string line, reading;
  for (std::smatch m; std::getline(in, line);) {
    if (std::regex_match(line, m, total)) {
      reading = m[1];
      continue;
    }
    if (std::regex_match(line, m, displacements)) {
      reading = "*U";
      continue;
    }
    std::istringstream row(line);
    if (reading == "*U") {
      int id;
      Eigen::Vector3d u;
      if (row >> id >> u.x() >> u.y() >> u.z() && id >= 1 && id <= int(job.nodes.size())) r.displacement[id - 1] = u;
    } else if (!reading.empty()) {
      Eigen::Vector3d f;
      if (row >> f.x() >> f.y() >> f.z()) r.reaction[reading] = f;
    }
  }
  for (const std::string& s : job.reactions)
    if (!r.reaction.count(s)) throw std::runtime_error("calculix: " + dat.string() + " has no total force for " + s);
  for (std::size_t i = 0; i < r.displacement.size(); ++i)
    if (!r.displacement[i].allFinite())
      throw std::runtime_error("calculix: " + dat.string() + " has no displacement of node " + std::to_string(i + 1));
  return r;
}

}  // namespace hcosim::adapters::reference
