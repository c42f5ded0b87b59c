// SPDX-License-Identifier: MIT
// focusmeter: an in-place passthrough GstBaseTransform (like `level`) that measures each frame's
// per-region sharpness and blur width on its own thread and posts them as `infocus` element
// messages (docs/gstreamer.md lists the fields), optionally as GstVideoRegionOfInterestMeta.
#pragma once

#include <gst/base/gstbasetransform.h>
#include <gst/gst.h>

G_BEGIN_DECLS

#define GST_TYPE_FOCUS_METER (gst_focus_meter_get_type())
G_DECLARE_FINAL_TYPE(GstFocusMeter, gst_focus_meter, GST, FOCUS_METER, GstBaseTransform)

GST_ELEMENT_REGISTER_DECLARE(focusmeter);

G_END_DECLS
