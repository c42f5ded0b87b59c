// SPDX-License-Identifier: MIT
/// @file image.h
/// Single-channel images (luma) shared by the metrics, blur and synthesis code.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

namespace infocus {

/// How a frame's grey levels encode light. Blur spreads light, so an edge's profile is measured in
/// linear light: the grey levels of an encoded frame are decoded first (docs/blur.md, Accuracy).
enum class TransferFunction {
    Linear,  ///< grey level proportional to light (raw sensor data, the synthetic generator)
    Srgb,    ///< IEC 61966-2-1 (JPEG files, most webcams and phone images)
    Rec709,  ///< ITU-R BT.709 camera curve (HD video)
};

/// The name of @p tf as the command line takes it: "linear", "srgb" or "rec709".
constexpr const char* transferFunctionName(TransferFunction tf) {
    switch (tf) {
        case TransferFunction::Srgb:
            return "srgb";
        case TransferFunction::Rec709:
            return "rec709";
        case TransferFunction::Linear:
            break;
    }
    return "linear";
}

/// The transfer function named @p name as transferFunctionName gives it; nullopt for any other.
constexpr std::optional<TransferFunction> transferFunctionFromName(std::string_view name) {
    for (const auto tf :
         {TransferFunction::Linear, TransferFunction::Srgb, TransferFunction::Rec709})
        if (name == transferFunctionName(tf)) return tf;
    return std::nullopt;
}

/// A read-only single-channel image. Pixels are borrowed; @ref storage keeps them alive when the
/// image owns them (a view into a frame keeps the frame's storage instead).
template <typename T>
struct ImageView {
    const T* data = nullptr;
    int width = 0;
    int height = 0;
    ptrdiff_t stride = 0;  ///< elements (not bytes) from one row to the next
    std::shared_ptr<const void> storage;

    /// Pointer to the first pixel of row @p y.
    const T* row(int y) const { return data + static_cast<ptrdiff_t>(y) * stride; }
    /// Pixel at column @p x, row @p y (no bounds check).
    T at(int x, int y) const { return row(y)[x]; }
    bool empty() const { return data == nullptr || width <= 0 || height <= 0; }
};

/// An axis-aligned rectangle of pixels: columns x..x+w-1, rows y..y+h-1.
struct Rect {
    int x = 0;
    int y = 0;
    int w = 0;
    int h = 0;
    bool operator==(const Rect&) const = default;
};

/// The part of @p r inside @p area: origin max(r, area) per axis, size the overlap (0 when they
/// do not meet). The far edges are added in 64 bits, so a rectangle reaching past INT_MAX (a
/// caller's arithmetic, a command line) clips instead of wrapping around.
inline Rect intersect(const Rect& r, const Rect& area) {
    const auto overlap = [](int a0, int aw, int b0, int bw) {
        const int64_t end = std::min(static_cast<int64_t>(a0) + aw, static_cast<int64_t>(b0) + bw);
        return static_cast<int>(std::max<int64_t>(0, end - std::max(a0, b0)));
    };
    return {std::max(r.x, area.x), std::max(r.y, area.y), overlap(r.x, r.w, area.x, area.w),
            overlap(r.y, r.h, area.y, area.h)};
}

/// 8-bit luma, 0..255.
using Luma8 = ImageView<uint8_t>;
/// 16-bit luma scaled to the full 0..65535 range whatever the source bit depth.
using Luma16 = ImageView<uint16_t>;

/// A writable image that owns its pixels; view() hands out a read-only view sharing them.
template <typename T>
class Image {
public:
    Image() = default;
    /// Allocates @p width × @p height pixels set to @p fill, tightly packed.
    Image(int width, int height, T fill = T{})
        : width_(width),
          height_(height),
          pixels_(std::make_shared<std::vector<T>>(static_cast<size_t>(width) * height, fill)) {}

    int width() const { return width_; }
    int height() const { return height_; }
    T* row(int y) { return pixels_->data() + static_cast<size_t>(y) * width_; }
    const T* row(int y) const { return pixels_->data() + static_cast<size_t>(y) * width_; }
    T& at(int x, int y) { return row(y)[x]; }
    T at(int x, int y) const { return row(y)[x]; }
    T* data() { return pixels_ ? pixels_->data() : nullptr; }
    const T* data() const { return pixels_ ? pixels_->data() : nullptr; }

    /// A read-only view sharing (and keeping alive) these pixels.
    ImageView<T> view() const { return ImageView<T>{data(), width_, height_, width_, pixels_}; }

private:
    int width_ = 0;
    int height_ = 0;
    std::shared_ptr<std::vector<T>> pixels_;
};

}  // namespace infocus
