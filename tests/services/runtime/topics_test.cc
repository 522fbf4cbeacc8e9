#include <set>

#include <gtest/gtest.h>

#include "services/runtime/topics.h"

namespace hcosim::services::runtime {
namespace {

// The type name we register must be the one fastddsgen wrote into the type
// support, or other DDS implementations will not match our topics.
TEST(Topics, TypeNamesMatchGeneratedTypeSupport) {
  int n = 0;
  for_each_topic([&](auto tag) {
    using T = typename decltype(tag)::type;
    typename TopicOf<T>::PubSub support;
    EXPECT_STREQ(support.getName(), TopicOf<T>::type_name);
    ++n;
  });
  EXPECT_EQ(n, 11);
}

TEST(Topics, NamesAreUniqueAndFindable) {
  std::set<std::string> names;
  for_each_topic([&](auto tag) { names.insert(TopicOf<typename decltype(tag)::type>::name); });
  EXPECT_EQ(names.size(), 11u);
  EXPECT_TRUE(names.count("DeformedMesh"));
  for (const auto& n : names) EXPECT_TRUE(with_topic(n, [](auto) {})) << n;
  EXPECT_FALSE(with_topic("NoSuchTopic", [](auto) {}));
}

TEST(Topics, ProfilesFollowTheContract) {
  EXPECT_STREQ(TopicOf<HapticState>::qos, "control");
  EXPECT_STREQ(TopicOf<ForceFeedback>::qos, "control");
  EXPECT_STREQ(TopicOf<DeformedMesh>::qos, "state");
  EXPECT_STREQ(TopicOf<MeshTopology>::qos, "latched");
  EXPECT_STREQ(TopicOf<ServiceStatus>::qos, "status");
  EXPECT_STREQ(TopicOf<ClockTick>::qos, "sequence");
}

}  // namespace
}  // namespace hcosim::services::runtime
