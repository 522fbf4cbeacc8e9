#include "adapters/device/friction_config.h"

namespace hcosim::adapters::device {

models::haptic::Friction friction_config(const Config& o) {
  if (!o.has("friction")) return {};
  if (!o.node()["friction"].IsMap()) {
    const double mu = o.number("friction", 0.3, 0, kMaxFriction);
    return {mu, mu};
  }
  const Config f = o.map("friction");
  f.allow_only({"static", "dynamic"});
  f.require({"static", "dynamic"}, "'friction'");
  const models::haptic::Friction out{f.number("static", 0, 0, kMaxFriction), f.number("dynamic", 0, 0, kMaxFriction)};
  if (out.dynamic_mu > out.static_mu) f.fail("dynamic", "'dynamic' friction must not exceed 'static'");
  return out;
}

}  // namespace hcosim::adapters::device
