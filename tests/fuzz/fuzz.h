// SPDX-License-Identifier: MIT
/// @file fuzz.h
/// What the libFuzzer harnesses share: the entry point each defines, the seed inputs each
/// generates, a scratch directory and a reader of the input's leading bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

/// libFuzzer's entry point: one input, never an exception or a crash.
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace infocus::fuzz {

/// Small valid inputs of the harness's kind (its seed corpus), generated rather than checked in.
std::vector<std::vector<uint8_t>> seeds();

/// A directory of this process for the files a harness writes (under /dev/shm when it exists,
/// so that writing an input per execution costs no disk).
const std::string& scratchDir();

/// Writes @p size bytes at @p data to @p path, replacing it; aborts when it cannot (the harness
/// would test nothing).
void writeFile(const std::string& path, const uint8_t* data, size_t size);

/// The whole of file @p path; aborts when it cannot be read.
std::vector<uint8_t> readFile(const std::string& path);

/// Opens the source named @p text and, if it starts, reads up to 16 frames, each converted to
/// luma (a frame that fails is skipped; the end of the stream ends the reading).
void readSource(const std::string& text);

/// Takes leading bytes of an input as small integers, then leaves the rest as a payload.
class Bytes {
public:
    Bytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
    /// The next byte, 0 past the end.
    uint8_t u8() { return size_ ? (--size_, *data_++) : 0; }
    /// The next two bytes, little-endian.
    uint16_t u16() {
        const unsigned low = u8();
        return static_cast<uint16_t>(low | (u8() << 8u));
    }
    /// Up to @p n bytes as a string.
    std::string str(size_t n) {
        n = n < size_ ? n : size_;
        std::string s(reinterpret_cast<const char*>(data_), n);
        data_ += n;
        size_ -= n;
        return s;
    }
    const uint8_t* data() const { return data_; }
    size_t size() const { return size_; }

private:
    const uint8_t* data_;
    size_t size_;
};

}  // namespace infocus::fuzz
