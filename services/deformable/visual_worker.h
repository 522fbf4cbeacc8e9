// One visual frame (every object's mesh) at a time on a thread of its own,
// so that mapping a dense mesh never delays a servo tick. A frame that
// finds the worker busy is dropped and counted as shed (ServiceStatus).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include <Eigen/Core>

#include "services/deformable/object_server.h"
#include "services/runtime/service.h"

namespace hcosim::services::deformable {

class VisualWorker {
 public:
  VisualWorker(runtime::Service& svc, runtime::Writer<DeformedMesh>& out, ObjectServer& objects);
  ~VisualWorker() { stop(); }
  VisualWorker(const VisualWorker&) = delete;
  VisualWorker& operator=(const VisualWorker&) = delete;
  // Publishes the frame in progress, then ends the thread.
  void stop();
  // Each object's cage, in order; false if the previous frame is still
  // being published. With `wait` (lockstep, where every frame must go out)
  // it waits for that frame instead.
  bool post(std::vector<Eigen::Matrix3Xd> cages, const StepStamp& stamp, bool wait);
  // What the frames cost and shed, for ObjectServer::report.
  ObjectServer::VisualStats stats() const { return {&frame_ms_, shed_busy_, link_shed_}; }

 private:
  void loop();

  runtime::Service& svc_;
  runtime::Writer<DeformedMesh>& out_;
  ObjectServer& objects_;
  std::mutex m_;
  std::condition_variable cv_;
  bool busy_ = false, stop_ = false;
  std::uint64_t shed_busy_ = 0;              // frames dropped: the worker was busy
  std::atomic<std::uint64_t> link_shed_{0};  // frames dropped: the paced link still carried the last one
  std::vector<Eigen::Matrix3Xd> cages_;
  StepStamp stamp_;
  DeformedMesh sample_;
  runtime::Window frame_ms_{1 << 12};
  std::thread thread_;  // last: starts once the rest is built
};

}  // namespace hcosim::services::deformable
