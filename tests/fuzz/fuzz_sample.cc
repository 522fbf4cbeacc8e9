// Incoming DDS samples: the bytes a reader's type support deserializes
// (first byte: which topic's type, the rest: the serialized payload), then
// hcosim's validation, which must refuse NaN and absurd values without
// crashing or allocating without bound.
#include <vector>

#include "adapters/validate.h"
#include "services/recording/recording.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::vector<std::uint8_t> payload(data + 1, data + size);
  std::size_t k = 0;
  return hcosim::fuzz::refuse_or_accept([&] {
    hcosim::services::runtime::for_each_topic([&](auto tag) {
      using T = typename decltype(tag)::type;
      if (k++ == data[0] % std::tuple_size_v<hcosim::services::runtime::AllTypes>)
        hcosim::adapters::validate(hcosim::services::recording::from_cdr<T>(payload));
    });
  });
}
