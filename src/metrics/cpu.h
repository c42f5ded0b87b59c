// SPDX-License-Identifier: MIT
// Internal: which vector kernels this CPU runs, asked once by every engine that has them.
#pragma once

namespace infocus::detail {

/// True when this CPU runs the AVX2 kernels (AVX2 and FMA).
bool haveAvx2();

}  // namespace infocus::detail
