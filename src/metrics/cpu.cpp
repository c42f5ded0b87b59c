// SPDX-License-Identifier: MIT
#include "cpu.h"

namespace infocus::detail {

bool haveAvx2() {
    static const bool have = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return have;
}

}  // namespace infocus::detail
