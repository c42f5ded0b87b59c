// SPDX-License-Identifier: MIT
/// @file output.h
/// Everything the commands write, for a tool that writes several kinds: each command's own
/// writers are in its header (analysis_output.h, depth_output.h, sweep_output.h, dof_output.h,
/// stack_output.h); the live state's JSON is in live.h.
#pragma once

#include "infocus/analysis_output.h"
#include "infocus/depth_output.h"
#include "infocus/dof_output.h"
#include "infocus/live.h"
#include "infocus/stack_output.h"
#include "infocus/sweep_output.h"
