// hcosim's topics as Foxglove's panels draw them (docs/foxglove.md): each
// object's surface a ::foxglove::SceneUpdate holding one triangle list, the
// stylus with the force it renders as an arrow, the camera's pose from the
// marker it tracks as ::foxglove::FrameTransforms, and its frames as
// ::foxglove::CompressedImage (JPEG). Every message is classic CDR of the
// schemas in idl/foxglove.idl, which Foxglove decodes with their OMG IDL.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "idl/haptic.h"
#include "idl/mesh.h"
#include "idl/rigid.h"
#include "idl/vision.h"
#include "models/render/shapes.h"

namespace hcosim::adapters::foxglove {

// One message of a Foxglove channel.
struct Message {
  std::string topic;              // "scene/organ", "scene/stylus", "tf", "image/cam"
  const char* schema = "";        // its schema's scoped name, e.g. "foxglove::SceneUpdate"
  std::vector<std::uint8_t> cdr;  // encapsulation header first
};

// idl/foxglove.idl as one self-contained OMG IDL text: the schema of every
// channel here, each naming its root type.
const char* schema_text();

// An object of the scene as the deployment names it; its colour is the AR
// view's for the same place in the list.
struct Item {
  std::string name;
  std::string kind;  // rigid or deformable
  double size = 0;   // rigid: half-edge or radius, m
};

struct Options {
  double rate_hz = 60;        // a rigid body's and the stylus's scene at most this often (their topics run at 1 kHz)
  double force_scale = 0.02;  // m of arrow per N, as the AR view's
  int jpeg_quality = 80;      // 0..100
  int tag_id = 0;             // the marker the world frame stands on
};

// The channel a sample is drawn on and its schema, known before it is
// drawn (a live bridge advertises the channel then and draws only what a
// client subscribes to). An empty topic: the sample draws nothing.
struct ChannelOf {
  std::string topic;
  const char* schema = "";
};

// Turns samples into the Foxglove messages they give, in the order they
// come. Deterministic: the same samples give the same bytes. Frames:
// "world" (the marker's, as the topics') and one per camera, named as
// the camera (OpenCV's optical axes, which Foxglove's image frames use).
class Builder {
 public:
  // Throws std::invalid_argument for a rate or quality out of range.
  explicit Builder(std::vector<Item> items, Options o = {});

  // A topology is kept for its mesh's next frames and gives nothing.
  std::vector<Message> on(const MeshTopology& t);
  // scene/NAME: none while its topology is missing or of another version.
  std::vector<Message> on(const DeformedMesh& m);
  // scene/NAME for a rigid item of the deployment (its size is not on the topic).
  std::vector<Message> on(const RigidBodyState& s);
  // scene/stylus: the tip, the pen, and the rendered force's arrow.
  std::vector<Message> on(const HapticState& s);
  // tf: world to the camera, from the scene's marker.
  std::vector<Message> on(const MarkerPose& p);
  // image/CAMERA: the frame as JPEG.
  std::vector<Message> on(const CameraFrame& f);
  // Topics with nothing to draw.
  template <class T>
  std::vector<Message> on(const T&) {
    return {};
  }

  // Where on(s) puts its message, if it gives one. Reads only what the
  // constructor set, so any thread may ask while another draws.
  ChannelOf channel(const DeformedMesh& m) const;
  ChannelOf channel(const RigidBodyState& s) const;
  ChannelOf channel(const HapticState& s) const;
  ChannelOf channel(const MarkerPose& p) const;
  ChannelOf channel(const CameraFrame& f) const;
  template <class T>
  ChannelOf channel(const T&) const {
    return {};
  }

  // Meshes given nothing: their topology was missing or did not match.
  std::uint64_t unmatched() const { return unmatched_; }

 private:
  struct Body {
    models::render::Mesh shape;  // in its own frame
    std::int64_t next_ns = 0;    // simulated time of its next scene
    std::size_t colour = 0;
  };

  bool due(std::int64_t& next_ns, std::int64_t sim_time_ns) const;
  std::size_t colour_of(const std::string& name);

  Options options_;
  std::vector<Item> items_;
  std::map<std::string, MeshTopology> topology_;
  std::map<std::string, Body> bodies_;
  std::map<std::string, std::size_t> colours_;  // objects not in items_, by first sight
  std::int64_t stylus_next_ns_ = 0;
  std::uint64_t unmatched_ = 0;
};

}  // namespace hcosim::adapters::foxglove
