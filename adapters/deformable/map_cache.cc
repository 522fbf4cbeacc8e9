#include "adapters/deformable/map_cache.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace hcosim::adapters::deformable {
namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t kMagic = 0x31'70'61'6d'6d'6f'63'68ULL;  // "hcommap1"

// FNV-1a over raw bytes: a cache key, not a defence against forgery.
struct Hash {
  std::uint64_t h = 1469598103934665603ULL;
  void bytes(const void* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<const unsigned char*>(p)[i]) * 1099511628211ULL;
  }
  template <class T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
};

std::uint64_t key(const models::deformable::HybridSpec& spec, const Eigen::Matrix3Xd& cage,
                  const std::vector<Eigen::Vector3i>& triangles, const Eigen::Matrix3Xd& points) {
  Hash h;
  h.value(int(spec.map));
  h.value(spec.map == models::deformable::VisualMap::mvc_sparse ? spec.keep : 1.0);
  h.value(cage.cols());
  h.bytes(cage.data(), sizeof(double) * cage.size());
  h.value(triangles.size());
  h.bytes(triangles.data(), sizeof(Eigen::Vector3i) * triangles.size());
  h.value(points.cols());
  h.bytes(points.data(), sizeof(double) * points.size());
  return h.h;
}

// The map in `path`, if it is one of rows x cols; else an empty matrix.
models::deformable::Weights read(const fs::path& path, Eigen::Index rows, Eigen::Index cols) {
  std::ifstream in(path, std::ios::binary);
  std::uint64_t magic = 0;
  std::int64_t r = 0, c = 0, nnz = 0;
  in.read(reinterpret_cast<char*>(&magic), sizeof magic);
  in.read(reinterpret_cast<char*>(&r), sizeof r);
  in.read(reinterpret_cast<char*>(&c), sizeof c);
  in.read(reinterpret_cast<char*>(&nnz), sizeof nnz);
  if (!in || magic != kMagic || r != rows || c != cols || nnz < 0 || nnz > rows * cols) return {};
  std::vector<int> outer(static_cast<std::size_t>(rows) + 1), inner(static_cast<std::size_t>(nnz));
  std::vector<double> values(static_cast<std::size_t>(nnz));
  in.read(reinterpret_cast<char*>(outer.data()), std::streamsize(sizeof(int) * outer.size()));
  in.read(reinterpret_cast<char*>(inner.data()), std::streamsize(sizeof(int) * inner.size()));
  in.read(reinterpret_cast<char*>(values.data()), std::streamsize(sizeof(double) * values.size()));
  if (!in || in.peek() != EOF || outer.front() != 0 || outer.back() != nnz) return {};
  for (std::size_t i = 0; i + 1 < outer.size(); ++i)
    if (outer[i] > outer[i + 1]) return {};
  for (int j : inner)
    if (j < 0 || j >= cols) return {};
  models::deformable::Weights w(rows, cols);
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(values.size());
  for (Eigen::Index i = 0; i < rows; ++i)
    for (int k = outer[std::size_t(i)]; k < outer[std::size_t(i) + 1]; ++k)
      t.emplace_back(int(i), inner[std::size_t(k)], values[std::size_t(k)]);
  w.setFromTriplets(t.begin(), t.end());
  return w;
}

// Writes `path` whole or not at all: `fill` writes a file beside it, which
// is renamed into place, so that runs sharing a folder never read half a
// file. A cache that cannot be written only costs the next start its time.
template <class Fill>
void write_whole(const fs::path& path, Fill&& fill) {
  const fs::path tmp = path.string() + "." + std::to_string(::getpid()) + ".tmp";
  std::error_code ec;
  {
    std::ofstream out(tmp, std::ios::binary);
    fill(out);
    if (!out) {
      fs::remove(tmp, ec);
      return;
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) fs::remove(tmp, ec);
}

void write(const fs::path& path, models::deformable::Weights w) {
  w.makeCompressed();
  write_whole(path, [&](std::ofstream& out) {
    const std::int64_t header[3] = {w.rows(), w.cols(), w.nonZeros()};
    out.write(reinterpret_cast<const char*>(&kMagic), sizeof kMagic);
    out.write(reinterpret_cast<const char*>(header), sizeof header);
    out.write(reinterpret_cast<const char*>(w.outerIndexPtr()), std::streamsize(sizeof(int) * (w.rows() + 1)));
    out.write(reinterpret_cast<const char*>(w.innerIndexPtr()), std::streamsize(sizeof(int) * w.nonZeros()));
    out.write(reinterpret_cast<const char*>(w.valuePtr()), std::streamsize(sizeof(double) * w.nonZeros()));
  });
}

constexpr std::uint64_t kGainMagic = 0x32'6e'69'61'67'6f'63'68ULL;  // "hcogain2": with the compliances

// The gain in `path` if it holds one; else an empty one.
models::deformable::ForceGain read_gain(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::uint64_t magic = 0;
  std::int64_t n = 0, stiff = 0;
  in.read(reinterpret_cast<char*>(&magic), sizeof magic);
  in.read(reinterpret_cast<char*>(&n), sizeof n);
  in.read(reinterpret_cast<char*>(&stiff), sizeof stiff);
  if (!in || magic != kGainMagic || n < 2 || n > 1000 || (stiff != 0 && stiff != 1)) return {};
  models::deformable::ForceGain g;
  for (auto* v : {&g.depth, &g.soft, &g.stiff}) {
    if (v == &g.stiff && !stiff) break;
    v->resize(std::size_t(n));
    in.read(reinterpret_cast<char*>(v->data()), std::streamsize(sizeof(double) * v->size()));
  }
  std::int64_t vertices = -1;
  in.read(reinterpret_cast<char*>(&g.soft_compliance), sizeof g.soft_compliance);
  in.read(reinterpret_cast<char*>(&g.stiff_compliance), sizeof g.stiff_compliance);
  in.read(reinterpret_cast<char*>(&vertices), sizeof vertices);
  if (!in || vertices < 0 || vertices > (std::int64_t(1) << 28)) return {};
  g.compliance.resize(std::size_t(vertices));
  in.read(reinterpret_cast<char*>(g.compliance.data()), std::streamsize(sizeof(double) * g.compliance.size()));
  if (!in || in.peek() != EOF || !(g.soft_compliance > 0) || (stiff && !(g.stiff_compliance > 0))) return {};
  return g;
}

void write_gain(const fs::path& path, const models::deformable::ForceGain& g) {
  write_whole(path, [&](std::ofstream& out) {
    const std::int64_t header[2] = {std::int64_t(g.depth.size()), g.stiff.empty() ? 0 : 1};
    out.write(reinterpret_cast<const char*>(&kGainMagic), sizeof kGainMagic);
    out.write(reinterpret_cast<const char*>(header), sizeof header);
    for (const auto* v : {&g.depth, &g.soft, &g.stiff})
      out.write(reinterpret_cast<const char*>(v->data()), std::streamsize(sizeof(double) * v->size()));
    const std::int64_t vertices = std::int64_t(g.compliance.size());
    out.write(reinterpret_cast<const char*>(&g.soft_compliance), sizeof g.soft_compliance);
    out.write(reinterpret_cast<const char*>(&g.stiff_compliance), sizeof g.stiff_compliance);
    out.write(reinterpret_cast<const char*>(&vertices), sizeof vertices);
    out.write(reinterpret_cast<const char*>(g.compliance.data()),
              std::streamsize(sizeof(double) * g.compliance.size()));
  });
}

}  // namespace

models::deformable::GainSource gain_cache(const std::string& dir) {
  return [dir](const models::deformable::HybridSpec& s, const models::deformable::Weights& map) {
    Hash h;
    for (const double v : models::deformable::gain_key(s)) h.value(v);
    char name[40];
    std::snprintf(name, sizeof name, "gain-%016llx.bin", static_cast<unsigned long long>(h.h));
    const fs::path path = fs::path(dir) / name;
    models::deformable::ForceGain g = read_gain(path);
    if (!g.depth.empty()) return g;
    g = models::deformable::force_gain(s, map);
    std::error_code ec;
    fs::create_directories(dir, ec);
    write_gain(path, g);
    return g;
  };
}

models::deformable::MapSource map_cache(const std::string& dir, const models::deformable::HybridSpec& spec) {
  return [dir, spec](const Eigen::Matrix3Xd& cage, const std::vector<Eigen::Vector3i>& triangles,
                     const Eigen::Matrix3Xd& points) {
    char name[32];
    std::snprintf(name, sizeof name, "map-%016llx.bin",
                  static_cast<unsigned long long>(key(spec, cage, triangles, points)));
    const fs::path path = fs::path(dir) / name;
    models::deformable::Weights w = read(path, points.cols(), cage.cols());
    if (w.rows() == points.cols()) return w;
    w = models::deformable::mvc_map(spec, cage, triangles, points);
    std::error_code ec;
    fs::create_directories(dir, ec);
    write(path, w);
    return w;
  };
}

}  // namespace hcosim::adapters::deformable
