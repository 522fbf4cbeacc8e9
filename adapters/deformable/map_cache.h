// A folder of visual maps (models::deformable::mvc_map) and force gains
// kept between runs: a restarted deformable service reads its hybrid
// objects' maps and gains instead of computing them again (about a second each at seed scale, where the
// restart should take well under 2 s; docs/deformable.md).
#pragma once

#include <string>

#include "models/deformable/hybrid.h"

namespace hcosim::adapters::deformable {

// A MapSource that returns the map from DIR/map-KEY.bin when that file
// holds it, KEY a 64-bit hash of every input of mvc_map (the cage, its
// triangles, the points, the map kind and `keep`), and otherwise computes
// it and writes that file (whole or not at all: written beside it, then
// renamed). A file that cannot be read as a map of the right shape is
// computed again and replaced. `dir` is made if missing.
models::deformable::MapSource map_cache(const std::string& dir, const models::deformable::HybridSpec& spec);

// A GainSource that keeps models::deformable::force_gain (seconds to
// compute) in DIR/gain-KEY.bin the same way, KEY a hash of
// gain_key(spec).
models::deformable::GainSource gain_cache(const std::string& dir);

}  // namespace hcosim::adapters::deformable
