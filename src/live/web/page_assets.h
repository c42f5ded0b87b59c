// SPDX-License-Identifier: MIT
/// @file page_assets.h
/// The web view's page (HTML, script, style) compiled into the binary by embed.py at build time.
#pragma once

#include <cstddef>
#include <span>

namespace infocus::web {

/// One file of the page: the URL path it is served at, its Content-Type and its bytes.
struct PageAsset {
    const char* path;         ///< "/", "/app.js", "/style.css"
    const char* contentType;  ///< e.g. "text/html; charset=utf-8"
    const unsigned char* data;
    size_t size;
};

/// Every file of the page (generated page_assets.cpp).
std::span<const PageAsset> pageAssets();

}  // namespace infocus::web
