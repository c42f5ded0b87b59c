// SPDX-License-Identifier: MIT
// Reused pixel buffers for frames and luma planes (buffer_pool.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace infocus::detail {

/// A zeroed buffer of @p bytes, taken from those recently released where one of that size
/// waits; released into the pool again when its last owner lets go.
std::shared_ptr<std::vector<uint8_t>> pooledBuffer(size_t bytes);

}  // namespace infocus::detail
