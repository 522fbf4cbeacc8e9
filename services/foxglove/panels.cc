#include "services/foxglove/panels.h"

#include <memory>
#include <type_traits>

#include "adapters/rigid/rigid_config.h"

namespace hcosim::services::foxglove {

std::vector<adapters::foxglove::Item> panel_items(const adapters::Deployment& d) {
  std::vector<adapters::foxglove::Item> items;
  for (const YAML::Node& o : d.scene.objects) {
    adapters::foxglove::Item it;
    it.name = o["name"].Scalar();
    it.kind = o["kind"].Scalar();
    if (it.kind == "rigid") it.size = adapters::rigid::body_size(adapters::Config(d.file, o));
    items.push_back(it);
  }
  return items;
}

recording::Derive panel_channels(std::vector<adapters::foxglove::Item> items, adapters::foxglove::Options o) {
  auto builder = std::make_shared<adapters::foxglove::Builder>(std::move(items), o);
  return [builder](const recording::Record& r) {
    std::vector<recording::Derived> out;
    runtime::with_topic(r.topic, [&](auto tag) {
      using T = typename decltype(tag)::type;
      // Only what is drawn is read back from its bytes (not the 1 kHz forces).
      constexpr bool drawn = std::is_same_v<T, MeshTopology> || std::is_same_v<T, DeformedMesh> ||
                             std::is_same_v<T, RigidBodyState> || std::is_same_v<T, HapticState> ||
                             std::is_same_v<T, MarkerPose> || std::is_same_v<T, CameraFrame>;
      if constexpr (drawn)
        for (adapters::foxglove::Message& m : builder->on(recording::from_cdr<T>(r.cdr)))
          out.push_back({std::move(m.topic), m.schema, adapters::foxglove::schema_text(), std::move(m.cdr)});
    });
    return out;
  };
}

}  // namespace hcosim::services::foxglove
