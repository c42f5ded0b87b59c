// SPDX-License-Identifier: MIT
/// @file recording_format.h
/// The on-disk layout of an infocus recording (format version 1).
///
/// A recording is a directory with two files:
///
/// - `header.json`: written once, before the first frame, through a temporary file and rename(),
///   so it is either absent or complete. Fields: `format` ("infocus-recording"),
///   `format_version` (integer; a reader refuses versions newer than it knows), `infocus_version`,
///   `source` (the source string that was recorded), `device`, `driver`, `pixel_format` (name),
///   `width_px`, `height_px`, `fps` (nominal, 0 when unknown), `created_unix_s`, and
///   `focus_control` (null, or `{min, max, step, default, unit}` in the control's native unit),
///   `transfer` (how the frames encode light: "linear", "srgb", "rec709" or null when unknown;
///   absent from older recordings), `transfer_origin` (where the source took it from),
///   `frames_file`.
///
/// - `frames.bin`: created first, exclusively, as the writer's claim on the directory, and held
///   under flock(LOCK_EX) while the recording is written. An append-only sequence of records,
///   one per frame, each written with a single
///   write() so that a process killed at any moment leaves every completed record intact and at
///   most one incomplete record at the end. A record is a fixed 128-byte little-endian
///   RecordHeader followed by `payloadBytes` bytes: the frame's planes, each exactly as captured
///   (with its stride), one after the other. `headerCrc` protects the header (lengths and
///   metadata), `payloadCrc` the payload; both are CRC-32 (IEEE 802.3, reflected, polynomial
///   0xEDB88320, as zlib and PNG). A reader indexes records by walking the headers and stops at
///   the first one that is incomplete or fails its CRC; a payload whose CRC fails makes only that
///   frame unreadable.
#pragma once

#include <cstddef>
#include <cstdint>

namespace infocus::replay {

/// The newest recording format this code reads and the one it writes.
inline constexpr int kRecordingFormatVersion = 1;
/// Name of the JSON header file inside a recording directory.
inline constexpr const char* kHeaderFileName = "header.json";
/// Name of the frame data file inside a recording directory.
inline constexpr const char* kFramesFileName = "frames.bin";
/// First four bytes of every record: "IFR1".
inline constexpr uint32_t kRecordMagic = 0x31524649u;

/// Bits of RecordHeader::flags.
enum RecordFlags : uint32_t {
    kFlagDroppedBefore = 1u << 0,    ///< the source skipped sequence numbers before this frame
    kFlagHasLens = 1u << 1,          ///< lensValue/lensUnit are valid
    kFlagHasLensDioptres = 1u << 2,  ///< lensDioptres is valid
    kFlagHasExposure = 1u << 3,      ///< exposureS is valid
};

/// The fixed header of one frame record (128 bytes, little-endian, no padding).
struct RecordHeader {
    uint32_t magic;          ///< kRecordMagic
    uint32_t headerBytes;    ///< sizeof(RecordHeader); lets later versions grow the header
    uint64_t payloadBytes;   ///< bytes of plane data following the header
    uint64_t sequence;       ///< the source's frame counter
    int64_t timestampNs;     ///< capture time, ns
    uint32_t pixelFormat;    ///< fourcc (PixelFormat value)
    int32_t width;           ///< pixels
    int32_t height;          ///< pixels
    uint32_t numPlanes;      ///< 1..3
    uint32_t stride[3];      ///< bytes per line of each plane (0 for compressed formats)
    uint32_t planeBytes[3];  ///< bytes of each plane in the payload; they sum to payloadBytes
    uint32_t flags;          ///< RecordFlags
    uint32_t reserved0;      ///< zero
    double lensValue;        ///< lens position in the control's native unit
    double lensDioptres;     ///< the same position in dioptres, when known
    double exposureS;        ///< exposure time, seconds
    char lensUnit[16];       ///< NUL-padded unit of lensValue ("dioptre", "v4l2", ...)
    uint32_t payloadCrc;     ///< CRC-32 of the payload
    uint32_t headerCrc;      ///< CRC-32 of the bytes of this header before this field
};
static_assert(sizeof(RecordHeader) == 128, "RecordHeader must stay 128 bytes");

/// CRC-32 (IEEE, reflected, init and final xor 0xFFFFFFFF) of @p size bytes at @p data,
/// continuing from @p crc (0 to start).
uint32_t crc32(const void* data, size_t size, uint32_t crc = 0);

}  // namespace infocus::replay
