// SPDX-License-Identifier: MIT
/// @file recording.h
/// Writing and reading infocus recordings: a directory with a JSON header and an append-only,
/// CRC-protected frame file (layout in replay/recording_format.h). Any pixel format, compressed
/// (MJPEG, variable size) or multi-planar, round-trips bit-exact with its per-frame metadata.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "infocus/error.h"
#include "infocus/frame.h"
#include "infocus/source.h"

namespace infocus {

/// What a recording says about its source, stored once in `header.json`.
struct RecordingHeader {
    int formatVersion = 0;       ///< format version the file was written with
    std::string infocusVersion;  ///< version of the infocus that wrote it
    std::string sourceString;    ///< the source string that was recorded
    std::string device;          ///< device node, camera id or file
    std::string driver;          ///< driver or backend name
    PixelFormat format = PixelFormat::Invalid;
    Size size;
    double fps = 0.0;                 ///< nominal frame rate, 0 when unknown
    std::optional<FocusRange> focus;  ///< the focus control, when the source had one
    /// How the frames encode light, as the source said (SourceInfo::transfer); header fields
    /// `transfer` (a transferFunctionName, or null) and `transfer_origin`.
    TransferReport transfer;
    int64_t createdUnixS = 0;  ///< wall-clock creation time, seconds since 1970
};

/// Builds a header describing @p info and, when non-null, @p focus.
RecordingHeader makeRecordingHeader(const SourceInfo& info, const FocusControl* focus);

/// Appends frames to a new recording directory. Every append() is one write() of a complete
/// record, so a process killed at any time leaves all completed frames readable.
class RecordingWriter {
public:
    /// Creates @p dir (which must not exist or be empty) and writes its header. Fails with
    /// ErrorKind::Usage when @p dir holds files, ErrorKind::Io when it cannot be created or when
    /// another writer claimed it first ("another recording is being written there").
    static Result<std::unique_ptr<RecordingWriter>> create(const std::string& dir,
                                                           const RecordingHeader& header);
    ~RecordingWriter();
    RecordingWriter(const RecordingWriter&) = delete;
    RecordingWriter& operator=(const RecordingWriter&) = delete;

    /// Appends @p frame with its metadata. A sequence gap since the previous frame sets the
    /// record's dropped flag. Fails with ErrorKind::Io (disk full, ...) or Usage (no planes).
    Status append(const Frame& frame);
    /// Forces written frames to the storage device (fdatasync).
    Status flush();
    /// Flushes and closes the file; later appends fail. Safe to call twice.
    Status close();

    /// Frames appended so far.
    uint64_t frames() const { return frames_; }
    /// Frames marked as following a sequence gap.
    uint64_t droppedFlags() const { return dropped_; }
    /// Bytes of the frame file so far.
    uint64_t bytes() const { return bytes_; }

private:
    RecordingWriter(std::string path, int fd) : path_(std::move(path)), fd_(fd) {}
    std::string path_;
    int fd_ = -1;
    uint64_t frames_ = 0;
    uint64_t dropped_ = 0;
    uint64_t bytes_ = 0;
    std::optional<uint64_t> lastSequence_;
};

/// Per-frame metadata of a recorded frame, available without reading its pixels.
struct RecordedFrameInfo {
    uint64_t sequence = 0;
    int64_t timestampNs = 0;
    bool droppedBefore = false;  ///< frames were lost right before this one
    uint64_t offset = 0;         ///< byte offset of the record in the frame file
    uint64_t payloadBytes = 0;
};

/// Reads a recording: indexes every complete record on open and reads frames by index.
class RecordingReader {
public:
    /// Opens the recording in @p dir. Fails with NotFound (no such directory or no header),
    /// Corrupt (unreadable header) or Unsupported (a newer format version). A damaged or
    /// incomplete record does not fail open(): the frames before it are indexed and damage()
    /// describes it.
    static Result<std::unique_ptr<RecordingReader>> open(const std::string& dir);
    ~RecordingReader();
    RecordingReader(const RecordingReader&) = delete;
    RecordingReader& operator=(const RecordingReader&) = delete;

    /// The recording's header.
    const RecordingHeader& header() const { return header_; }
    /// Number of complete frames indexed.
    size_t frameCount() const { return index_.size(); }
    /// Metadata of frame @p i (0-based, < frameCount()).
    const RecordedFrameInfo& frameInfo(size_t i) const { return index_[i]; }
    /// Why indexing stopped before the end of the file (an incomplete or damaged record), or
    /// nullopt when the file ended cleanly after the last record.
    const std::optional<std::string>& damage() const { return damage_; }
    /// Reads frame @p i with its metadata. Fails with Corrupt (naming the file, frame and
    /// offset) when its payload fails the CRC or its record header no longer fits the file, Io
    /// on a read error, Usage for i out of range.
    Result<Frame> read(size_t i) const;
    /// The frame file's path.
    const std::string& path() const { return path_; }

private:
    RecordingReader() = default;
    std::string path_;
    int fd_ = -1;
    uint64_t fileSize_ = 0;  ///< bytes of the frame file when it was indexed
    RecordingHeader header_;
    std::vector<RecordedFrameInfo> index_;
    std::optional<std::string> damage_;
};

}  // namespace infocus
