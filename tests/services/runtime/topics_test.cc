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

// One instance, one handle, whatever key was hashed before (KeyedPubSubType):
// the same handle as a type support that hashes it first, whose key buffer
// is all zeros as DDS-XTypes' key hash has it.
template <class T>
void expect_one_handle(const T& a, const T& b) {
  using eprosima::fastrtps::rtps::InstanceHandle_t;
  typename TopicOf<T>::PubSub fresh, used;
  InstanceHandle_t reference, first, other, again;
  ASSERT_TRUE(fresh.getKey(const_cast<T*>(&a), &reference));
  used.getKey(const_cast<T*>(&a), &first);
  used.getKey(const_cast<T*>(&b), &other);
  used.getKey(const_cast<T*>(&a), &again);
  EXPECT_EQ(first, reference);
  EXPECT_EQ(again, reference);
  EXPECT_NE(other, reference);
}

TEST(Topics, AnInstancesHandleDoesNotDependOnTheKeyHashedBefore) {
  // Keys whose first member's length leaves padding before the next.
  ForceFeedback live, b;
  live.source("live"), live.device("omni");
  b.source("b"), b.device("omni");
  expect_one_handle(live, b);
  MarkerPose cam, left;
  cam.camera("cam1"), cam.tag_id(3);
  left.camera("left_camera"), left.tag_id(3);
  expect_one_handle(cam, left);
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
