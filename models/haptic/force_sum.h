// The force a device outputs from many sources (every object the stylus
// can touch answers on its own): the sum of each source's latest local
// model at the device's position, a source that stopped answering
// dropping out after a timeout.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include <Eigen/Core>

#include "models/haptic/local_model.h"

namespace hcosim::models::haptic {

class ForceSum {
 public:
  // timeout_s: a source's model counts for this long after it arrived (> 0).
  explicit ForceSum(double timeout_s);

  // The latest model from `source`, arrived at time t (s).
  void set(const std::string& source, const LocalModel& model, double t);

  // Drops the sources older than the timeout at time t, counted in expired().
  void expire(double t);
  // Sum over the sources still fresh at time t of their models at x (m,
  // world), after expire(t). Each source's share is left in force_of().
  Eigen::Vector3d total(double t, const Eigen::Vector3d& x);

  std::size_t sources() const { return latest_.size(); }  // fresh at the last total()
  bool has(const std::string& source) const { return latest_.count(source) > 0; }
  // Whether `source`'s latest model is a free-space one that reaches x
  // (models::haptic::covers; its age against kFreeHorizonS is the caller's to check).
  bool covers(const std::string& source, const Eigen::Vector3d& x) const;
  // `source`'s force in the last total() (zero if it had none).
  Eigen::Vector3d force_of(const std::string& source) const;
  std::uint64_t expired() const { return expired_; }

 private:
  struct Latest {
    LocalModel model;
    double t;
    Eigen::Vector3d rendered = Eigen::Vector3d::Zero();
  };
  double timeout_;
  std::map<std::string, Latest> latest_;
  std::uint64_t expired_ = 0;
};

}  // namespace hcosim::models::haptic
