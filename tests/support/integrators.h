// The behavior model's integrators, for tests that run each case over every
// one of them (TEST_P suites named ...PerIntegrator, one test per integrator).
#pragma once

#include <string>

#include <gtest/gtest.h>

#include "models/massspring/integrator.h"

namespace hcosim::tests {

inline constexpr models::massspring::Integrator kIntegrators[] = {
    models::massspring::Integrator::symplectic_euler, models::massspring::Integrator::velocity_verlet,
    models::massspring::Integrator::rk4, models::massspring::Integrator::implicit_euler,
    models::massspring::Integrator::local_global};

// The test's suffix: the integrator's name, as deployments spell it.
inline std::string integrator_name(const ::testing::TestParamInfo<models::massspring::Integrator>& info) {
  return models::massspring::name(info.param);
}

}  // namespace hcosim::tests
