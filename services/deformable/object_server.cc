#include "services/deformable/object_server.h"

#include <algorithm>
#include <mutex>

#include "adapters/deformable/mesh_idl.h"
#include "models/deformable/hybrid.h"

namespace hcosim::services::deformable {

namespace {

// How far the HIP may go with nothing of the object near.
double free_clearance(const models::deformable::Object& o, const Eigen::Vector3d& hip) {
  return o.reach().exteriorDistance(hip) - ObjectServer::kFreeMarginM;
}

// What the device feels from one object's touch, with the local model it
// renders until the next answer: stiffness along the face's normal (in a
// grab the object pulls, so no one-sided test).
adapters::device::Feel feel(const models::deformable::Touch& t, const Eigen::Vector3d& hip, bool grab,
                            double clearance) {
  if (!t.in_contact) return adapters::device::free_feel(hip, clearance);
  adapters::device::Feel f = adapters::device::contact_feel(t.force, hip, t.normal, t.stiffness, t.depth,
                                                            adapters::device::kContactModelRadius);
  if (grab) f.normal.setZero();
  return f;
}

}  // namespace

ObjectServer::ObjectServer(const adapters::deformable::DeformableConfig& config, double servo_dt, bool realtime,
                           const std::string& cache, std::FILE* log)
    : device_(config.device), servo_dt_(servo_dt), realtime_(realtime) {
  for (const adapters::deformable::ObjectConfig& o : config.objects) {
    if (o.model == "hybrid") {
      const models::deformable::HybridSpec& s = o.hybrid;
      if (s.shape.triangles.empty())
        std::fprintf(log,
                     "%s: hybrid, %d^3 chains and masses, %d visual vertices by %s; building the map (kept in %s)\n",
                     o.name.c_str(), s.elements, 6 * s.visual_subdivisions * s.visual_subdivisions + 2,
                     models::deformable::name(s.map), cache.c_str());
      else
        std::fprintf(
            log,
            "%s: hybrid from a mesh, %d nodes along its longest side, %d visual vertices by %s; building the map "
            "(kept in %s)\n",
            o.name.c_str(), s.elements, int(s.shape.vertices.cols()), models::deformable::name(s.map), cache.c_str());
      std::fflush(log);
    }
    Item item;
    item.name = o.name;
    const std::int64_t t0 = runtime::mono_ns();
    item.model = adapters::deformable::make_object(o, cache);
    if (o.model == "hybrid") {
      std::fprintf(log, "%s: built in %.1f s\n", o.name.c_str(), (runtime::mono_ns() - t0) * 1e-9);
      std::fflush(log);
    }
    items_.push_back(std::move(item));
  }
}

void ObjectServer::answer(const HapticState& s, const StepStamp& stamp,
                          const std::function<void(ForceFeedback&)>& write) {
  const std::int64_t t0 = runtime::mono_ns();
  const Eigen::Vector3d hip = adapters::device::from_idl(s.position());
  const bool grab = s.buttons() & 1u;
  const auto one = [&](Item& it, bool answered) {
    models::deformable::Touch t;
    double clearance;
    {
      std::lock_guard<runtime::PiMutex> l(*it.lock);
      t = it.model->touch(servo_dt_, hip, grab);
      clearance = free_clearance(*it.model, hip);
    }
    it.contacts += t.in_contact;
    it.max_force = std::max(it.max_force, t.force.norm());
    if (!answered && !t.in_contact) return ++answers_.unanswered, void();
    it.said = feel(t, hip, grab, clearance);
    it.said_seq = s.seq();
    ForceFeedback f = adapters::device::force_feedback(it.name, device_, s.seq(), stamp, it.said);
    write(f);
  };
  // Pass 0 answers the objects the device waits for, pass 1 touches the
  // rest: each once, as it was before pass 0 gave some a new answer.
  for (Item& it : items_)
    it.covered = realtime_ && adapters::device::answer_covered(it.said, it.said_seq, hip, s.seq(), servo_dt_);
  for (int pass = 0; pass < 2; ++pass)
    for (Item& it : items_)
      if (it.covered == (pass == 1)) one(it, !it.covered);
  answers_.us.add((runtime::mono_ns() - t0) * 1e-3);
}

void ObjectServer::advance(double now) {
  const std::int64_t t0 = runtime::mono_ns();
  bool stepped = false;
  for (Item& it : items_) {
    const double dt = it.model->behavior_dt();
    for (; dt > 0 && it.behavior_time + 0.5 * dt <= now + servo_dt_; it.behavior_time += dt) {
      {
        std::lock_guard<runtime::PiMutex> l(*it.lock);
        it.model->couple();
      }
      it.model->integrate();
      stepped = true;
    }
  }
  if (stepped) behavior_us_.add((runtime::mono_ns() - t0) * 1e-3);
}

std::vector<Eigen::Matrix3Xd> ObjectServer::cages() const {
  std::vector<Eigen::Matrix3Xd> out;
  for (const Item& it : items_) {
    std::lock_guard<runtime::PiMutex> l(*it.lock);
    out.push_back(it.model->cage());
  }
  return out;
}

void ObjectServer::mesh(std::size_t k, const Eigen::Matrix3Xd& cage, const StepStamp& stamp, DeformedMesh& sample) {
  Item& it = items_[k];
  adapters::deformable::fill_mesh(sample, it.name, stamp, it.model->surface_from(cage), it.model->triangles());
  ++it.frames;
}

std::vector<MeshTopology> ObjectServer::topologies() const {
  std::vector<MeshTopology> out;
  for (const Item& it : items_)
    out.push_back(adapters::deformable::mesh_topology(it.name, int(it.model->surface().cols()), it.model->triangles()));
  return out;
}

void ObjectServer::report(std::FILE* out, const std::string& service, const VisualStats& visual) const {
  for (const Item& it : items_)
    std::fprintf(out, "%s: %llu ticks in contact, max force %.3f N, %llu meshes published\n", it.name.c_str(),
                 static_cast<unsigned long long>(it.contacts), it.max_force,
                 static_cast<unsigned long long>(it.frames));
  answers_.report_unanswered(out, service, "object");
  const runtime::Window none;
  const runtime::Window& frame_ms = visual.frame_ms ? *visual.frame_ms : none;
  std::fprintf(
      out,
      "%s: haptic answer (all objects) p50 %.1f us p99 %.1f us over %zu states; "
      "behavior p50 %.1f us p99 %.1f us; "
      "visual frame (all objects) p50 %.2f ms p99 %.2f ms, %llu shed (worker busy), %llu shed (link busy, network "
      "bulk_mbit)\n",
      service.c_str(), answers_.us.percentile(0.5), answers_.us.percentile(0.99), answers_.us.size(),
      behavior_us_.percentile(0.5), behavior_us_.percentile(0.99), frame_ms.percentile(0.5), frame_ms.percentile(0.99),
      static_cast<unsigned long long>(visual.shed_busy), static_cast<unsigned long long>(visual.shed_link));
}

}  // namespace hcosim::services::deformable
