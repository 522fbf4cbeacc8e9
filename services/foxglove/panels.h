// The Foxglove panels' channels of a recording (adapters/foxglove/panels.h) from the
// records a recorder takes, with the objects a deployment gives.
#pragma once

#include <string>
#include <vector>

#include "adapters/deployment.h"
#include "adapters/foxglove/panels.h"
#include "services/recording/recording.h"

namespace hcosim::services::foxglove {

// The scene's objects in the file's order (the AR view's colours), a rigid
// body's size as the rigid service reads it.
std::vector<adapters::foxglove::Item> panel_items(const adapters::Deployment& d);

// Each record's Foxglove messages. Not thread-safe: the recorder calls it
// under its lock.
recording::Derive panel_channels(std::vector<adapters::foxglove::Item> items, adapters::foxglove::Options o);

}  // namespace hcosim::services::foxglove
