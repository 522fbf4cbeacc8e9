#include "services/deformable/visual_worker.h"

#include "services/runtime/realtime.h"

namespace hcosim::services::deformable {

VisualWorker::VisualWorker(runtime::Service& svc, runtime::Writer<DeformedMesh>& out, ObjectServer& objects)
    : svc_(svc), out_(out), objects_(objects), thread_([this] { loop(); }) {}

void VisualWorker::stop() {
  {
    std::lock_guard<std::mutex> l(m_);
    stop_ = true;
  }
  cv_.notify_one();
  if (thread_.joinable()) thread_.join();
}

bool VisualWorker::post(std::vector<Eigen::Matrix3Xd> cages, const StepStamp& stamp, bool wait) {
  std::unique_lock<std::mutex> l(m_);
  if (wait) cv_.wait(l, [this] { return !busy_; });
  if (busy_) {
    svc_.shed_output();
    ++shed_busy_;
    return false;
  }
  busy_ = true, cages_ = std::move(cages), stamp_ = stamp;
  cv_.notify_one();
  return true;
}

void VisualWorker::loop() {
  runtime::lower_to_normal();  // meshes go after every haptic-rate thread (the camera's and view's peers)
  std::unique_lock<std::mutex> l(m_);
  for (;;) {
    cv_.wait(l, [this] { return stop_ || busy_; });
    if (busy_) {
      l.unlock();
      const std::int64_t t0 = runtime::mono_ns();
      // Paced (network bulk_mbit): a link still carrying the last frame
      // drops this one, counted, rather than queueing it behind.
      const bool shed = out_.paced() && !out_.caught_up();
      if (shed) svc_.shed_output(), ++link_shed_;
      for (std::size_t k = 0; k < objects_.size() && !shed; ++k) {
        objects_.mesh(k, cages_[k], stamp_, sample_);
        out_.write(sample_);
      }
      l.lock();
      frame_ms_.add((runtime::mono_ns() - t0) * 1e-6);
      busy_ = false;
      cv_.notify_all();  // a waiting post()
    }
    if (stop_) return;
  }
}

}  // namespace hcosim::services::deformable
