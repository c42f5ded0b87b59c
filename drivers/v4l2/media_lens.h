// SPDX-License-Identifier: MIT
/// @file media_lens.h
/// Lens sub-devices found through the media controller: a camera sensor's entity has an ancillary
/// link to a lens entity (dw9714, ad5820, vimc's "Lens A"), whose V4L2 sub-device node carries
/// V4L2_CID_FOCUS_ABSOLUTE. Internal to the capture backends (includes the kernel header).
#pragma once

#include <linux/media.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "infocus/devices.h"
#include "infocus/error.h"
#include "infocus/source.h"

namespace infocus::v4l2 {

/// A media device's graph as MEDIA_IOC_G_TOPOLOGY reports it.
struct MediaGraph {
    struct Entity {
        uint32_t id = 0;
        uint32_t function = 0;  ///< MEDIA_ENT_F_*
        std::string name;
    };
    struct Interface {
        uint32_t id = 0;
        uint32_t type = 0;  ///< MEDIA_INTF_T_*
        uint32_t major = 0, minor = 0;
    };
    struct Pad {
        uint32_t id = 0;
        uint32_t entity = 0;
        uint32_t flags = 0;  ///< MEDIA_PAD_FL_*
    };
    /// A data link joins pads; an interface link joins an interface (source) to an entity
    /// (sink); an ancillary link joins a primary entity (source) to an ancillary one (sink).
    struct Link {
        uint32_t source = 0, sink = 0;
        uint32_t flags = 0;  ///< MEDIA_LNK_FL_*
    };
    std::vector<Entity> entities;
    std::vector<Interface> interfaces;
    std::vector<Pad> pads;
    std::vector<Link> links;
};

/// Copies the arrays a MEDIA_IOC_G_TOPOLOGY call filled (ptr_* and num_* of @p t).
MediaGraph graphFromTopology(const media_v2_topology& t);

/// A lens entity of a graph, the sensor it belongs to, and its sub-device's device number.
struct LensLink {
    std::string sensor;  ///< the sensor entity's name
    std::string lens;    ///< the lens entity's name
    uint32_t major = 0, minor = 0;
};

/// The lens of the sensor entity @p sensorId: its ancillary link to a MEDIA_ENT_F_LENS entity
/// that has a sub-device interface. nullopt when it has none.
std::optional<LensLink> lensOfSensor(const MediaGraph& g, uint32_t sensorId);

/// The lens of the sensor that feeds the video node with device number @p major:@p minor: from
/// the node's entity upstream over enabled data links to the nearest camera sensor with a lens.
std::optional<LensLink> lensOfVideoNode(const MediaGraph& g, uint32_t major, uint32_t minor);

/// A lens sub-device found for a camera.
struct LensNode {
    std::string node;    ///< `/dev/v4l-subdevN`
    std::string lens;    ///< the lens entity's name
    std::string sensor;  ///< the sensor entity's name
    std::string media;   ///< `/dev/mediaN`
};

/// The lens of the sensor feeding capture node @p videoPath, searched in every /dev/media*.
std::optional<LensNode> findLensOfVideoNode(const std::string& videoPath);

/// The lens of the sensor libcamera calls @p cameraId: its firmware node path, or for sensors
/// without one `<sysfs device path> <entity name>` (vimc: `platform/vimc.0 Sensor B`).
std::optional<LensNode> findLensOfCamera(const std::string& cameraId);

/// FOCUS_ABSOLUTE of @p lens as a FocusControl (unit "v4l2"); every set is read back.
Result<std::unique_ptr<FocusControl>> openLensFocus(const LensNode& lens, int settleFrames);

/// FOCUS_ABSOLUTE of @p lens for `infocus devices` (DeviceControl::device names the node).
std::optional<DeviceControl> describeLens(const LensNode& lens);

}  // namespace infocus::v4l2
