// Recordings (recording/recording.h, hcosim's format or MCAP) as `hcosim
// export` and `replay` read them: every record's CDR bytes decoded as its
// topic's type, then validated as a sample arriving over DDS would be.
#include "adapters/validate.h"
#include "services/recording/recording.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = hcosim::fuzz::scratch(data, size, ".rec");
  return hcosim::fuzz::refuse_or_accept([&] {
    hcosim::services::recording::RecordingReader in(path);
    for (hcosim::services::recording::Record r; in.next(r);)
      hcosim::services::runtime::with_topic(r.topic, [&](auto tag) {
        using T = typename decltype(tag)::type;
        hcosim::adapters::validate(hcosim::services::recording::from_cdr<T>(r.cdr));
      });
  });
}
