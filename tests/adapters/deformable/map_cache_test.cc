// The hybrid objects' visual maps kept on disk (adapters/deformable/
// map_cache): a miss computes and keeps the map, a hit reads back exactly
// that map, other inputs miss, and a damaged file is computed again.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "adapters/deformable/map_cache.h"
#include "tests/support/temp_dir.h"

namespace hcosim::adapters::deformable {

// The deformable models this adapter converts.
using namespace models::deformable;
namespace {

namespace fs = std::filesystem;

class MapCache : public ::testing::Test {
 protected:
  void SetUp() override {
    spec.elements = 4;
    spec.visual_subdivisions = 6;
  }
  std::vector<fs::path> files() const {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path());
    return out;
  }
  static bool same(const Weights& a, const Weights& b) {
    return a.rows() == b.rows() && a.cols() == b.cols() && a.nonZeros() == b.nonZeros() &&
           Eigen::MatrixXd(a - b).cwiseAbs().maxCoeff() == 0;
  }
  tests::TempDir tmp;
  fs::path dir = tmp.path / "cache";  // made by the cache itself
  HybridSpec spec;
};

TEST_F(MapCache, AMissComputesAndKeepsTheMapAHitReadsItBackExactly) {
  const Hybrid computed(spec);
  const Hybrid first(spec, map_cache(dir, spec));
  EXPECT_TRUE(same(first.map(), computed.map()));
  ASSERT_EQ(files().size(), 1u);
  const Hybrid second(spec, map_cache(dir, spec));
  EXPECT_TRUE(same(second.map(), computed.map()));
  EXPECT_EQ(files().size(), 1u);
}

TEST_F(MapCache, AHitComesFromTheFile) {
  const Hybrid first(spec, map_cache(dir, spec));
  // Plant another map of the same shape under the same key: it is what a
  // hit returns, so the map was read, not computed.
  HybridSpec other = spec;
  other.keep = 0.9;
  const Hybrid planted(other, map_cache(dir / "other", other));
  ASSERT_FALSE(same(planted.map(), first.map()));
  fs::copy_file(fs::directory_iterator(dir / "other")->path(), files().front(), fs::copy_options::overwrite_existing);
  fs::remove_all(dir / "other");
  EXPECT_TRUE(same(Hybrid(spec, map_cache(dir, spec)).map(), planted.map()));
}

TEST_F(MapCache, OtherInputsMissAndADamagedFileIsComputedAgain) {
  const Hybrid computed(spec);
  (void)Hybrid(spec, map_cache(dir, spec));
  const fs::path mine = files().front();
  const auto size = fs::file_size(mine);
  HybridSpec moved = spec;
  moved.centre.x() += 0.01;
  (void)Hybrid(moved, map_cache(dir, moved));
  EXPECT_EQ(files().size(), 2u);
  fs::resize_file(mine, size / 2);
  EXPECT_TRUE(same(Hybrid(spec, map_cache(dir, spec)).map(), computed.map()));
  EXPECT_EQ(fs::file_size(mine), size);
  std::ofstream(mine, std::ios::trunc) << "not a map";
  EXPECT_TRUE(same(Hybrid(spec, map_cache(dir, spec)).map(), computed.map()));
  EXPECT_EQ(fs::file_size(mine), size);
}

// The force gain: a miss computes and keeps it, a hit reads back exactly
// that, from the file (a planted gain is what comes back), and another
// spec or a damaged file computes it again.
TEST_F(MapCache, TheForceGainIsKeptTooAndReadFromItsFile) {
  const ForceGain computed = force_gain(spec);
  const ForceGain first = gain_cache(dir.string())(spec, {});
  EXPECT_EQ(first.depth, computed.depth);
  EXPECT_EQ(first.soft, computed.soft);
  EXPECT_EQ(first.soft_compliance, computed.soft_compliance);
  EXPECT_EQ(first.compliance, computed.compliance);
  EXPECT_EQ(first.compliance.size(), std::size_t(hybrid_visual(spec).vertices.cols()));
  ASSERT_EQ(files().size(), 1u);
  const fs::path file = files().front();
  HybridSpec stiff = spec;
  stiff.stiff_ratio = 3;
  const ForceGain other = gain_cache((dir / "other").string())(stiff, {});
  ASSERT_FALSE(other.stiff.empty());
  fs::copy_file(fs::directory_iterator(dir / "other")->path(), file, fs::copy_options::overwrite_existing);
  EXPECT_EQ(gain_cache(dir.string())(spec, {}).stiff, other.stiff);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << "not a gain";
  EXPECT_EQ(gain_cache(dir.string())(spec, {}).soft, computed.soft);
  EXPECT_EQ(Hybrid(spec, {}, gain_cache(dir.string())).gain().soft, computed.soft);
}

}  // namespace
}  // namespace hcosim::adapters::deformable
