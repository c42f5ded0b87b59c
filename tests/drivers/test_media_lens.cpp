// SPDX-License-Identifier: MIT
// The lens lookup on a media graph built in memory as MEDIA_IOC_G_TOPOLOGY fills it: vimc's graph
// in Linux 6.1 (drivers/media/test-drivers/vimc/vimc-core.c: its entities, its data links with
// their default enabled flags, and the ancillary links Sensor A → Lens A, Sensor B → Lens B).
#include <catch2/catch.hpp>

#include <cstring>
#include <string>
#include <vector>

#include "drivers/v4l2/media_lens.h"

using infocus::v4l2::graphFromTopology;
using infocus::v4l2::lensOfSensor;
using infocus::v4l2::lensOfVideoNode;
using infocus::v4l2::MediaGraph;

namespace {

constexpr uint32_t kMajor = 81;

// Builds the kernel's arrays, as the ioctl fills them, with the ids the kernel would give.
struct Topology {
    std::vector<media_v2_entity> entities;
    std::vector<media_v2_interface> interfaces;
    std::vector<media_v2_pad> pads;
    std::vector<media_v2_link> links;
    uint32_t next = 1;

    uint32_t entity(const char* name, uint32_t function) {
        media_v2_entity e{};
        e.id = next++;
        std::strncpy(e.name, name, sizeof e.name - 1);
        e.function = function;
        entities.push_back(e);
        return e.id;
    }
    uint32_t pad(uint32_t entity, uint32_t flags) {
        media_v2_pad p{};
        p.id = next++;
        p.entity_id = entity;
        p.flags = flags;
        pads.push_back(p);
        return p.id;
    }
    void link(uint32_t source, uint32_t sink, uint32_t flags) {
        media_v2_link l{};
        l.id = next++;
        l.source_id = source;
        l.sink_id = sink;
        l.flags = flags;
        links.push_back(l);
    }
    // A device node for @p entity, linked to it.
    void node(uint32_t entity, uint32_t type, uint32_t minor) {
        media_v2_interface i{};
        i.id = next++;
        i.intf_type = type;
        i.devnode.major = kMajor;
        i.devnode.minor = minor;
        interfaces.push_back(i);
        link(i.id, entity, MEDIA_LNK_FL_INTERFACE_LINK | MEDIA_LNK_FL_ENABLED);
    }
    MediaGraph graph() {
        media_v2_topology t{};
        t.num_entities = uint32_t(entities.size());
        t.ptr_entities = reinterpret_cast<uintptr_t>(entities.data());
        t.num_interfaces = uint32_t(interfaces.size());
        t.ptr_interfaces = reinterpret_cast<uintptr_t>(interfaces.data());
        t.num_pads = uint32_t(pads.size());
        t.ptr_pads = reinterpret_cast<uintptr_t>(pads.data());
        t.num_links = uint32_t(links.size());
        t.ptr_links = reinterpret_cast<uintptr_t>(links.data());
        return graphFromTopology(t);
    }
};

constexpr uint32_t kOn = MEDIA_LNK_FL_DATA_LINK | MEDIA_LNK_FL_ENABLED;
constexpr uint32_t kOnFixed = kOn | MEDIA_LNK_FL_IMMUTABLE;
constexpr uint32_t kOff = MEDIA_LNK_FL_DATA_LINK;

// Device minors: the three capture nodes, then the sub-devices.
constexpr uint32_t kRaw0 = 0, kRaw1 = 1, kRgb = 2, kLensA = 10, kLensB = 11;

struct Vimc {
    Topology t;
    uint32_t sensorA, sensorB, input, debayerAOut, debayerBOut, inputOut, scalerIn;
    uint32_t debayerToScalerA, debayerToScalerB, inputToScaler;  // link indices

    Vimc() {
        const uint32_t src = MEDIA_PAD_FL_SOURCE, sink = MEDIA_PAD_FL_SINK;
        sensorA = t.entity("Sensor A", MEDIA_ENT_F_CAM_SENSOR);
        sensorB = t.entity("Sensor B", MEDIA_ENT_F_CAM_SENSOR);
        const uint32_t debA = t.entity("Debayer A", MEDIA_ENT_F_PROC_VIDEO_PIXEL_ENC_CONV);
        const uint32_t debB = t.entity("Debayer B", MEDIA_ENT_F_PROC_VIDEO_PIXEL_ENC_CONV);
        const uint32_t raw0 = t.entity("Raw Capture 0", MEDIA_ENT_F_IO_V4L);
        const uint32_t raw1 = t.entity("Raw Capture 1", MEDIA_ENT_F_IO_V4L);
        input = t.entity("RGB/YUV Input", MEDIA_ENT_F_CAM_SENSOR);
        const uint32_t scaler = t.entity("Scaler", MEDIA_ENT_F_PROC_VIDEO_SCALER);
        const uint32_t rgb = t.entity("RGB/YUV Capture", MEDIA_ENT_F_IO_V4L);
        const uint32_t lensA = t.entity("Lens A", MEDIA_ENT_F_LENS);
        const uint32_t lensB = t.entity("Lens B", MEDIA_ENT_F_LENS);

        const uint32_t sAout = t.pad(sensorA, src), sBout = t.pad(sensorB, src);
        const uint32_t dAin = t.pad(debA, sink);
        debayerAOut = t.pad(debA, src);
        const uint32_t dBin = t.pad(debB, sink);
        debayerBOut = t.pad(debB, src);
        const uint32_t r0in = t.pad(raw0, sink), r1in = t.pad(raw1, sink);
        inputOut = t.pad(input, src);
        scalerIn = t.pad(scaler, sink);
        const uint32_t scalerOut = t.pad(scaler, src), rgbIn = t.pad(rgb, sink);

        t.link(sAout, dAin, kOnFixed);
        t.link(sAout, r0in, kOnFixed);
        t.link(sBout, dBin, kOnFixed);
        t.link(sBout, r1in, kOnFixed);
        debayerToScalerA = uint32_t(t.links.size());
        t.link(debayerAOut, scalerIn, kOn);
        debayerToScalerB = uint32_t(t.links.size());
        t.link(debayerBOut, scalerIn, kOff);
        inputToScaler = uint32_t(t.links.size());
        t.link(inputOut, scalerIn, kOff);
        t.link(scalerOut, rgbIn, kOnFixed);
        t.link(sensorA, lensA, MEDIA_LNK_FL_ANCILLARY_LINK | MEDIA_LNK_FL_ENABLED);
        t.link(sensorB, lensB, MEDIA_LNK_FL_ANCILLARY_LINK | MEDIA_LNK_FL_ENABLED);

        t.node(raw0, MEDIA_INTF_T_V4L_VIDEO, kRaw0);
        t.node(raw1, MEDIA_INTF_T_V4L_VIDEO, kRaw1);
        t.node(rgb, MEDIA_INTF_T_V4L_VIDEO, kRgb);
        uint32_t minor = 3;
        for (uint32_t e : {sensorA, sensorB, debA, debB, input, scaler})
            t.node(e, MEDIA_INTF_T_V4L_SUBDEV, minor++);
        t.node(lensA, MEDIA_INTF_T_V4L_SUBDEV, kLensA);
        t.node(lensB, MEDIA_INTF_T_V4L_SUBDEV, kLensB);
    }
    void enable(uint32_t link, bool on) { t.links[link].flags = on ? kOn : kOff; }
};

}  // namespace

TEST_CASE("the topology arrays are copied whole") {
    Vimc v;
    const MediaGraph g = v.t.graph();
    CHECK(g.entities.size() == 11);
    CHECK(g.pads.size() == v.t.pads.size());
    CHECK(g.links.size() == v.t.links.size());
    REQUIRE(g.interfaces.size() == 11);
    CHECK(g.entities[0].name == "Sensor A");
    CHECK(g.entities[10].function == MEDIA_ENT_F_LENS);
    CHECK(g.interfaces[2].major == kMajor);
    CHECK(g.interfaces[2].minor == kRgb);
}

TEST_CASE("each raw capture node finds the lens of the sensor that feeds it") {
    Vimc v;
    const MediaGraph g = v.t.graph();
    auto a = lensOfVideoNode(g, kMajor, kRaw0);
    REQUIRE(a);
    CHECK(a->sensor == "Sensor A");
    CHECK(a->lens == "Lens A");
    CHECK(a->major == kMajor);
    CHECK(a->minor == kLensA);
    auto b = lensOfVideoNode(g, kMajor, kRaw1);
    REQUIRE(b);
    CHECK(b->lens == "Lens B");
    CHECK(b->minor == kLensB);
}

TEST_CASE("the scaler's node follows whichever debayer link is enabled") {
    Vimc v;
    auto byDefault = lensOfVideoNode(v.t.graph(), kMajor, kRgb);
    REQUIRE(byDefault);
    CHECK(byDefault->lens == "Lens A");
    // libcamera's vimc pipeline feeds the scaler from Sensor B.
    v.enable(v.debayerToScalerA, false);
    v.enable(v.debayerToScalerB, true);
    auto configured = lensOfVideoNode(v.t.graph(), kMajor, kRgb);
    REQUIRE(configured);
    CHECK(configured->sensor == "Sensor B");
    CHECK(configured->minor == kLensB);
    // The test-pattern input is a sensor entity without a lens.
    v.enable(v.debayerToScalerB, false);
    v.enable(v.inputToScaler, true);
    CHECK_FALSE(lensOfVideoNode(v.t.graph(), kMajor, kRgb));
}

TEST_CASE("no lens where the graph has none") {
    Vimc v;
    // A device number the graph does not hold, and a sub-device's (not a video node's).
    CHECK_FALSE(lensOfVideoNode(v.t.graph(), kMajor, 99));
    CHECK_FALSE(lensOfVideoNode(v.t.graph(), kMajor, kLensA));
    CHECK_FALSE(lensOfSensor(v.t.graph(), v.input));
    REQUIRE(lensOfSensor(v.t.graph(), v.sensorB));
    // An ancillary entity that is not a lens (a flash), and a lens without a node.
    Topology t;
    const uint32_t sensor = t.entity("imx219", MEDIA_ENT_F_CAM_SENSOR);
    const uint32_t flash = t.entity("flash", MEDIA_ENT_F_FLASH);
    const uint32_t lens = t.entity("dw9714", MEDIA_ENT_F_LENS);
    t.link(sensor, flash, MEDIA_LNK_FL_ANCILLARY_LINK | MEDIA_LNK_FL_ENABLED);
    t.link(sensor, lens, MEDIA_LNK_FL_ANCILLARY_LINK | MEDIA_LNK_FL_ENABLED);
    t.node(flash, MEDIA_INTF_T_V4L_SUBDEV, 5);
    CHECK_FALSE(lensOfSensor(t.graph(), sensor));
    t.node(lens, MEDIA_INTF_T_V4L_SUBDEV, 6);
    auto found = lensOfSensor(t.graph(), sensor);
    REQUIRE(found);
    CHECK(found->lens == "dw9714");
    CHECK(found->minor == 6);
}
