// SPDX-License-Identifier: MIT
// The GStreamer plugin `infocus`: its one element, focusmeter.
#include <gst/gst.h>

#include "gstfocusmeter.h"
#include "infocus_config.h"

namespace {

gboolean pluginInit(GstPlugin* plugin) {
    return GST_ELEMENT_REGISTER(focusmeter, plugin);
}

}  // namespace

#define PACKAGE "infocus"
GST_PLUGIN_DEFINE(GST_VERSION_MAJOR, GST_VERSION_MINOR, infocus,
                  "Focus and blur measurement of video frames (infocus)", pluginInit,
                  INFOCUS_VERSION, "MIT/X11", "infocus", "infocus")
