// The scene channels of a recording (adapters/scene/scene.h) from the
// records a recorder takes, with the objects a deployment gives.
#pragma once

#include <string>
#include <vector>

#include "adapters/scene/scene.h"
#include "services/runtime/deployment.h"
#include "services/runtime/recording.h"

namespace hcosim::services::foxglove {

// The scene's objects in the file's order (the AR view's colours), a rigid
// body's size as the rigid service reads it; the scene's marker id.
std::vector<adapters::scene::Item> scene_items(const runtime::Deployment& d);
int scene_tag_id(const runtime::Deployment& d);

// Each record's Foxglove messages. Not thread-safe: the recorder calls it
// under its lock.
runtime::Derive scene_channels(std::vector<adapters::scene::Item> items, adapters::scene::Options o);

}  // namespace hcosim::services::foxglove
