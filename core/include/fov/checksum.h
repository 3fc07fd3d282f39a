#pragma once

#include <cstddef>
#include <cstdint>

namespace fov {

// CRC-32C (Castagnoli), as in iSCSI and ext4; hardware-accelerated with SSE4.2.
uint32_t crc32c(const void* data, size_t bytes, uint32_t crc = 0);

}  // namespace fov
