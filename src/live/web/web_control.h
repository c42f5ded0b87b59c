// SPDX-License-Identifier: MIT
// The page's commands (POST /control): one JSON object naming one command, checked and sent to
// LiveControls.
#pragma once

#include <string>
#include <string_view>

#include "infocus/live.h"

namespace infocus::web {

/// What a command did: the HTTP status and the JSON body to answer with.
struct ControlReply {
    int httpStatus = 200;  ///< 200, 400 (bad JSON or value), 409 (no lens motor), 503 (closing)
    std::string body;      ///< {"ok": true, "status": "..."} or {"error": "..."}
};

/// Runs the command in @p body on @p controls. @p hasFocusControl: whether the source can move
/// its lens (focus commands are refused with 409 otherwise).
ControlReply runControl(std::string_view body, LiveControls& controls, bool hasFocusControl);

/// Whether @p given equals the secret @p expected, in a time that depends neither on their
/// contents nor on where they differ: both become SHA-256 digests, compared in all 32 bytes.
bool sameSecret(std::string_view given, std::string_view expected);

/// {"error": message} as one line of JSON.
std::string errorJson(std::string_view message);

}  // namespace infocus::web
