// Taking raw IDL samples from a reader, for readers outside the typed Reader<Plain> (ROS 2 and PX4
// types, disposed instances): batches of loans, each sample seen while its loan is held, then the
// loans returned.
#pragma once

#include <array>
#include <string>

#include "service/dds/dds_entities.hpp"

namespace skyroute::dds {

// Calls on(sample, info) for every sample in states `mask` (invalid ones too: check
// info.valid_data). The sample is valid only during the call.
template <class Wire, class OnSample>
Status takeLoaned(dds_entity_t reader, uint32_t mask, const std::string& what, OnSample&& on) {
  constexpr std::size_t kBatch = 32;
  for (;;) {
    std::array<void*, kBatch> loans{};
    std::array<dds_sample_info_t, kBatch> infos{};
    const dds_return_t n = dds_take_mask(reader, loans.data(), infos.data(), kBatch, kBatch, mask);
    if (n < 0) return ddsError(n, "dds_take on " + what);
    for (dds_return_t i = 0; i < n; ++i) on(*static_cast<const Wire*>(loans[i]), infos[i]);
    if (n > 0) {
      const dds_return_t rc = dds_return_loan(reader, loans.data(), n);
      if (rc != DDS_RETCODE_OK) return ddsError(rc, "dds_return_loan on " + what);
    }
    if (static_cast<std::size_t>(n) < kBatch) return Status::success();
  }
}

}  // namespace skyroute::dds
