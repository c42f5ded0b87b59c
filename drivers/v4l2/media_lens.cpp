// SPDX-License-Identifier: MIT
#include "drivers/v4l2/media_lens.h"

#include <dirent.h>
#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <set>
#include <utility>

#include "drivers/common/mode_choice.h"

namespace infocus::v4l2 {

namespace {

// Built without the rest of the V4L2 backend (the libcamera module uses it): its own ioctl.
int xioctl(int fd, unsigned long request, void* arg) {
    int r;
    do {
        r = ::ioctl(fd, request, arg);
    } while (r < 0 && errno == EINTR);
    return r < 0 ? -errno : 0;
}

std::string errnoText(int err) {
    return std::strerror(err < 0 ? -err : err);
}

uint32_t linkType(uint32_t flags) {
    return flags & MEDIA_LNK_FL_LINK_TYPE;
}

const MediaGraph::Entity* entity(const MediaGraph& g, uint32_t id) {
    for (const auto& e : g.entities)
        if (e.id == id) return &e;
    return nullptr;
}

const MediaGraph::Pad* pad(const MediaGraph& g, uint32_t id) {
    for (const auto& p : g.pads)
        if (p.id == id) return &p;
    return nullptr;
}

// The interface of @p type linked to entity @p entityId.
const MediaGraph::Interface* interfaceOf(const MediaGraph& g, uint32_t entityId, uint32_t type) {
    for (const auto& l : g.links) {
        if (linkType(l.flags) != MEDIA_LNK_FL_INTERFACE_LINK || l.sink != entityId) continue;
        for (const auto& i : g.interfaces)
            if (i.id == l.source && i.type == type) return &i;
    }
    return nullptr;
}

std::string readLine(const std::string& path) {
    std::ifstream in(path);
    std::string s;
    std::getline(in, s);
    return s;
}

std::optional<std::string> realPath(const std::string& path) {
    char buf[PATH_MAX];
    if (!::realpath(path.c_str(), buf)) return std::nullopt;
    return std::string(buf);
}

// The node of char device major:minor, from the DEVNAME its sysfs uevent file gives.
std::optional<std::string> charDeviceNode(uint32_t major, uint32_t minor) {
    std::ifstream in("/sys/dev/char/" + std::to_string(major) + ":" + std::to_string(minor) +
                     "/uevent");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("DEVNAME=", 0) == 0) return "/dev/" + line.substr(8);
    return std::nullopt;
}

std::vector<std::string> mediaNodes() {
    std::vector<std::string> out;
    if (DIR* dir = ::opendir("/dev")) {
        while (const dirent* e = ::readdir(dir))
            if (std::strncmp(e->d_name, "media", 5) == 0)
                out.push_back(std::string("/dev/") + e->d_name);
        ::closedir(dir);
    }
    std::sort(out.begin(), out.end(), [](const std::string& a, const std::string& b) {
        return a.size() != b.size() ? a.size() < b.size() : a < b;
    });
    return out;
}

// Two MEDIA_IOC_G_TOPOLOGY calls: the counts, then the arrays; again if the graph changed between.
Result<MediaGraph> readGraph(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
    if (fd < 0)
        return makeError(ErrorKind::Device, path + ": cannot open: " + errnoText(errno), errno);
    for (int attempt = 0; attempt < 3; ++attempt) {
        media_v2_topology t{};
        if (int r = xioctl(fd, MEDIA_IOC_G_TOPOLOGY, &t); r < 0) {
            ::close(fd);
            return makeError(ErrorKind::Device,
                             path + ": MEDIA_IOC_G_TOPOLOGY failed: " + errnoText(r), -r);
        }
        const uint64_t version = t.topology_version;
        std::vector<media_v2_entity> ents(t.num_entities);
        std::vector<media_v2_interface> intfs(t.num_interfaces);
        std::vector<media_v2_pad> pads(t.num_pads);
        std::vector<media_v2_link> links(t.num_links);
        t.ptr_entities = reinterpret_cast<uintptr_t>(ents.data());
        t.ptr_interfaces = reinterpret_cast<uintptr_t>(intfs.data());
        t.ptr_pads = reinterpret_cast<uintptr_t>(pads.data());
        t.ptr_links = reinterpret_cast<uintptr_t>(links.data());
        const int r = xioctl(fd, MEDIA_IOC_G_TOPOLOGY, &t);
        // ENOSPC: an array grew since the first call.
        if (r == -ENOSPC || (r == 0 && t.topology_version != version)) continue;
        ::close(fd);
        if (r < 0)
            return makeError(ErrorKind::Device,
                             path + ": MEDIA_IOC_G_TOPOLOGY failed: " + errnoText(r), -r);
        return graphFromTopology(t);
    }
    ::close(fd);
    return makeError(ErrorKind::Device, path + ": the media graph kept changing while read");
}

std::optional<LensNode> toNode(const LensLink& l, const std::string& media) {
    auto node = charDeviceNode(l.major, l.minor);
    if (!node) return std::nullopt;
    return LensNode{*node, l.lens, l.sensor, media};
}

// The ids libcamera may give sensor entity @p sensor: its device's firmware node path (device
// tree or ACPI), else for a platform device `<path under /sys/devices> <entity name>`.
std::vector<std::string> cameraIds(const MediaGraph& g, const MediaGraph::Entity& sensor) {
    std::vector<std::string> ids;
    const auto* intf = interfaceOf(g, sensor.id, MEDIA_INTF_T_V4L_SUBDEV);
    if (!intf) return ids;
    auto dev = realPath("/sys/dev/char/" + std::to_string(intf->major) + ":" +
                        std::to_string(intf->minor) + "/device");
    if (!dev) return ids;
    if (auto of = realPath(*dev + "/of_node")) {
        const std::string base = "/sys/firmware/devicetree";
        if (of->rfind(base, 0) == 0) ids.push_back(of->substr(base.size()));
    }
    if (std::string acpi = readLine(*dev + "/firmware_node/path"); !acpi.empty())
        ids.push_back(acpi);
    const std::string sys = "/sys/devices/";
    if (dev->rfind(sys, 0) == 0) ids.push_back(dev->substr(sys.size()) + " " + sensor.name);
    return ids;
}

// FOCUS_ABSOLUTE on a lens sub-device; the node is the lens's alone, so every set reads back.
class SubdevFocus : public FocusControl {
public:
    SubdevFocus(int fd, std::string node, v4l2_queryctrl q, int settle)
        : fd_(fd), node_(std::move(node)), q_(q), settle_(settle) {}
    ~SubdevFocus() override { ::close(fd_); }
    SubdevFocus(const SubdevFocus&) = delete;
    SubdevFocus& operator=(const SubdevFocus&) = delete;

    FocusRange range() const override {
        return {double(q_.minimum), double(q_.maximum), double(q_.step), double(q_.default_value),
                "v4l2"};
    }

    Result<LensPosition> get() override {
        auto v = read();
        if (!v) return v.error();
        return LensPosition{double(*v), "v4l2", std::nullopt};
    }

    Status set(double value) override {
        const auto v = static_cast<int32_t>(
            capture::snapToStep(value, q_.minimum, q_.maximum, std::max(q_.step, 1)));
        v4l2_control c{};
        c.id = V4L2_CID_FOCUS_ABSOLUTE;
        c.value = v;
        if (int r = xioctl(fd_, VIDIOC_S_CTRL, &c); r < 0)
            return makeError(ErrorKind::Device,
                             node_ + ": the lens refused focus_absolute " + std::to_string(v) +
                                 ": " + errnoText(r),
                             -r);
        auto back = read();
        if (!back) return back.error();
        if (*back != v)
            return makeError(ErrorKind::Device, node_ + ": focus_absolute set to " +
                                                    std::to_string(v) + " reads back " +
                                                    std::to_string(*back));
        return {};
    }

    int settleFrames() const override { return settle_; }

private:
    Result<int32_t> read() const {
        v4l2_control c{};
        c.id = V4L2_CID_FOCUS_ABSOLUTE;
        if (int r = xioctl(fd_, VIDIOC_G_CTRL, &c); r < 0)
            return makeError(ErrorKind::Device,
                             node_ + ": cannot read focus_absolute: " + errnoText(r), -r);
        return c.value;
    }

    int fd_;
    std::string node_;
    v4l2_queryctrl q_;
    int settle_;
};

// Opens @p node and describes its FOCUS_ABSOLUTE; the fd is closed unless @p keep takes it.
Result<v4l2_queryctrl> queryLens(const std::string& node, int* keep) {
    const int fd = ::open(node.c_str(), O_RDWR | O_CLOEXEC);
    if (fd < 0)
        return makeError(ErrorKind::Device, node + ": cannot open the lens: " + errnoText(errno),
                         errno);
    v4l2_queryctrl q{};
    q.id = V4L2_CID_FOCUS_ABSOLUTE;
    if (int r = xioctl(fd, VIDIOC_QUERYCTRL, &q); r < 0 || (q.flags & V4L2_CTRL_FLAG_DISABLED)) {
        ::close(fd);
        return makeError(ErrorKind::Unsupported, node + ": the lens has no focus_absolute control" +
                                                     (r < 0 ? " (" + errnoText(r) + ")" : ""));
    }
    if (keep)
        *keep = fd;
    else
        ::close(fd);
    return q;
}

}  // namespace

MediaGraph graphFromTopology(const media_v2_topology& t) {
    MediaGraph g;
    const auto* ents = reinterpret_cast<const media_v2_entity*>(uintptr_t(t.ptr_entities));
    const auto* intfs = reinterpret_cast<const media_v2_interface*>(uintptr_t(t.ptr_interfaces));
    const auto* pads = reinterpret_cast<const media_v2_pad*>(uintptr_t(t.ptr_pads));
    const auto* links = reinterpret_cast<const media_v2_link*>(uintptr_t(t.ptr_links));
    for (uint32_t i = 0; ents && i < t.num_entities; ++i)
        g.entities.push_back(
            {ents[i].id, ents[i].function, std::string(ents[i].name, strnlen(ents[i].name, 64))});
    for (uint32_t i = 0; intfs && i < t.num_interfaces; ++i)
        g.interfaces.push_back(
            {intfs[i].id, intfs[i].intf_type, intfs[i].devnode.major, intfs[i].devnode.minor});
    for (uint32_t i = 0; pads && i < t.num_pads; ++i)
        g.pads.push_back({pads[i].id, pads[i].entity_id, pads[i].flags});
    for (uint32_t i = 0; links && i < t.num_links; ++i)
        g.links.push_back({links[i].source_id, links[i].sink_id, links[i].flags});
    return g;
}

std::optional<LensLink> lensOfSensor(const MediaGraph& g, uint32_t sensorId) {
    const auto* sensor = entity(g, sensorId);
    if (!sensor) return std::nullopt;
    for (const auto& l : g.links) {
        if (linkType(l.flags) != MEDIA_LNK_FL_ANCILLARY_LINK || l.source != sensorId) continue;
        const auto* lens = entity(g, l.sink);
        if (!lens || lens->function != MEDIA_ENT_F_LENS) continue;
        if (const auto* i = interfaceOf(g, lens->id, MEDIA_INTF_T_V4L_SUBDEV))
            return LensLink{sensor->name, lens->name, i->major, i->minor};
    }
    return std::nullopt;
}

std::optional<LensLink> lensOfVideoNode(const MediaGraph& g, uint32_t major, uint32_t minor) {
    const MediaGraph::Interface* video = nullptr;
    for (const auto& i : g.interfaces)
        if (i.type == MEDIA_INTF_T_V4L_VIDEO && i.major == major && i.minor == minor) video = &i;
    if (!video) return std::nullopt;
    // Breadth first from the node's entities, so the nearest sensor wins.
    std::deque<uint32_t> todo;
    std::set<uint32_t> seen;
    for (const auto& l : g.links)
        if (linkType(l.flags) == MEDIA_LNK_FL_INTERFACE_LINK && l.source == video->id)
            todo.push_back(l.sink);
    while (!todo.empty()) {
        const uint32_t id = todo.front();
        todo.pop_front();
        if (!seen.insert(id).second) continue;
        const auto* e = entity(g, id);
        if (e && e->function == MEDIA_ENT_F_CAM_SENSOR)
            if (auto lens = lensOfSensor(g, id)) return lens;
        // Upstream: enabled data links into this entity's sink pads.
        for (const auto& l : g.links) {
            if (linkType(l.flags) != MEDIA_LNK_FL_DATA_LINK || !(l.flags & MEDIA_LNK_FL_ENABLED))
                continue;
            const auto* sink = pad(g, l.sink);
            const auto* source = pad(g, l.source);
            if (sink && source && sink->entity == id) todo.push_back(source->entity);
        }
    }
    return std::nullopt;
}

std::optional<LensNode> findLensOfVideoNode(const std::string& videoPath) {
    struct stat st {};
    if (::stat(videoPath.c_str(), &st) < 0 || !S_ISCHR(st.st_mode)) return std::nullopt;
    for (const auto& media : mediaNodes()) {
        auto g = readGraph(media);
        if (!g) continue;
        if (auto l = lensOfVideoNode(*g, ::major(st.st_rdev), ::minor(st.st_rdev)))
            return toNode(*l, media);
    }
    return std::nullopt;
}

std::optional<LensNode> findLensOfCamera(const std::string& cameraId) {
    for (const auto& media : mediaNodes()) {
        auto g = readGraph(media);
        if (!g) continue;
        for (const auto& e : g->entities) {
            if (e.function != MEDIA_ENT_F_CAM_SENSOR) continue;
            const auto ids = cameraIds(*g, e);
            if (std::find(ids.begin(), ids.end(), cameraId) == ids.end()) continue;
            if (auto l = lensOfSensor(*g, e.id)) return toNode(*l, media);
            return std::nullopt;
        }
    }
    return std::nullopt;
}

Result<std::unique_ptr<FocusControl>> openLensFocus(const LensNode& lens, int settleFrames) {
    int fd = -1;
    auto q = queryLens(lens.node, &fd);
    if (!q) return q.error();
    return std::unique_ptr<FocusControl>(
        std::make_unique<SubdevFocus>(fd, lens.node, *q, settleFrames));
}

std::optional<DeviceControl> describeLens(const LensNode& lens) {
    int fd = -1;
    auto q = queryLens(lens.node, &fd);
    if (!q) return std::nullopt;
    DeviceControl c;
    c.name = "focus_absolute";
    c.unit = "v4l2";
    c.min = q->minimum;
    c.max = q->maximum;
    c.step = q->step;
    c.defaultValue = q->default_value;
    v4l2_control v{};
    v.id = V4L2_CID_FOCUS_ABSOLUTE;
    if (xioctl(fd, VIDIOC_G_CTRL, &v) == 0) c.current = v.value;
    ::close(fd);
    c.device = lens.node;
    c.lens = lens.lens + " of " + lens.sensor;
    return c;
}

}  // namespace infocus::v4l2
