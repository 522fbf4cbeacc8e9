// The force a device outputs from many sources (every object the stylus
// can touch publishes its own): the sum of each source's latest force, a
// source that stopped publishing dropping out after a timeout.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include <Eigen/Core>

namespace hcosim::haptic {

class ForceSum {
 public:
  // timeout_s: a source's force counts for this long after it arrived (> 0).
  explicit ForceSum(double timeout_s);

  // The latest force (world frame, N) from `source`, arrived at time t (s).
  void set(const std::string& source, const Eigen::Vector3d& force, double t);

  // Sum of the forces still fresh at time t; sources older than the
  // timeout are dropped and counted in expired().
  Eigen::Vector3d total(double t);

  std::size_t sources() const { return latest_.size(); }  // fresh at the last total()
  std::uint64_t expired() const { return expired_; }

 private:
  struct Latest {
    Eigen::Vector3d force;
    double t;
  };
  double timeout_;
  std::map<std::string, Latest> latest_;
  std::uint64_t expired_ = 0;
};

}  // namespace hcosim::haptic
