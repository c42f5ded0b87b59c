#!/bin/sh
# /init of the test VM: loads vivid and vimc, starts udev for libcamera, runs infocus against the
# real drivers and prints every result as "@@TAG ..." lines that tests/vm/check.py judges.
export PATH=/bin:/sbin:/usr/bin:/usr/sbin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
mount -t tmpfs tmp /tmp
mount -t tmpfs run /run
ln -sf infocus.bin /bin/infocus

for m in $(cat /mods/order); do
	case $m in
	vivid.ko) insmod /mods/vivid.ko n_devs=1 node_types=0x101 ;;
	*) insmod /mods/$m ;;
	esac
done
insmod /mods/vimc.ko 2>/dev/null
/lib/systemd/systemd-udevd --daemon 2>/dev/null
udevadm trigger --action=add
udevadm settle --timeout=20

# run TAG COMMAND...: the command's stdout, stderr and exit status, tagged.
run() {
	tag=$1
	shift
	"$@" >/tmp/out 2>/tmp/err
	rc=$?
	sed "s/^/@@$tag.out /" /tmp/out
	sed "s/^/@@$tag.err /" /tmp/err
	echo "@@$tag.rc $rc"
}

# vivid's nodes, found by name in sysfs (numbering depends on load order).
cap=""
out=""
for n in /sys/class/video4linux/video*; do
	name=$(cat "$n/name")
	case $name in
	vivid-000-vid-cap) cap=/dev/$(basename "$n") ;;
	vivid-000-vid-out) out=/dev/$(basename "$n") ;;
	esac
done
echo "@@nodes cap=$cap out=$out"
v4l2-ctl -d "$cap" -L 2>&1 | sed 's/^/@@diag /'

# a. discovery
run a infocus devices --json
run a_text infocus devices
run a_unit test_drivers_v4l2_device

# b. capture and analysis from both backends
run b_v4l2_rec infocus record "v4l2:$cap" -o /tmp/rec_v4l2 --frames 6
run b_v4l2_ana infocus analyze /tmp/rec_v4l2 --grid 4x3
run b_lc_rec infocus record libcamera:0 -o /tmp/rec_lc --frames 4
run b_lc_ana infocus analyze /tmp/rec_lc --grid 4x3

# h. the GStreamer element on vivid's webcam input: v4l2src ! focusmeter ! fakesink posts its
# messages and ends at num-buffers with EOS; only the plugins in /gst, scanned in-process
if [ -f /gst/libgstinfocus.so ]; then
	export GST_PLUGIN_SYSTEM_PATH=/gst GST_REGISTRY=/tmp/gst-registry.bin GST_REGISTRY_FORK=no
	run h_gst gst-launch-1.0 -m v4l2src device=$cap num-buffers=30 ! \
		video/x-raw,width=320,height=180 ! focusmeter grid=4x3 interval=0 ! fakesink
	unset GST_PLUGIN_SYSTEM_PATH GST_REGISTRY GST_REGISTRY_FORK
else
	echo "@@h_gst.skip the build has no GStreamer plugin (src/gstreamer)"
fi

# e. the transfer function the camera's format names, on vivid's webcam input (before part c
# turns on its loopback, which reports the output's): the colour space's own, then BT.709, none
# (linear) and SMPTE 2084 set by its Transfer Function control; then libcamera's colour space
v4l2-ctl -d "$cap" -i 0
for x in 0 1 5 7; do
	v4l2-ctl -d "$cap" -c transfer_function=$x 2>&1 | sed "s/^/@@diag_e /"
	run e_$x infocus analyze "v4l2:$cap,size=320x180" --frames 1 --grid 2x2 --transfer auto
	[ $x = 1 ] && run e_dev infocus devices --json
done
v4l2-ctl -d "$cap" -c transfer_function=0
run e_lc infocus analyze libcamera:0 --frames 1 --grid 2x2 --transfer auto

# f. focus sweep: a sweep where the camera has a focus control, a refusal where it has none
run f_v4l2 infocus sweep "v4l2:$cap,size=320x180" --steps 3 --refine 0 --grid 2x2 --no-blur --json
run f_lc infocus sweep libcamera:0 --steps 3 --refine 0 --grid 2x2 --no-blur --json

# g. the live assistant's JSON face for five seconds on each camera (vivid on its webcam input).
# Small modes: under emulation vimc's 1920x1080 default gives one analysed frame in 1.5 s. vimc
# takes only widths and heights that are multiples of 6 (its scaler triples the sensor's size).
run g_v4l2 infocus live "v4l2:$cap,size=320x180" --ui json --seconds 5
run g_lc infocus live libcamera:0,size=720x480 --ui json --seconds 5

# c. loopback: frames of known blur through vivid's output node into its capture node. S-Video
# takes only interlaced fields at NTSC size; with the same size, format and field on both sides
# vivid copies the output buffer line by line, and then draws its OSD text over the top left.
v4l2-ctl -d "$cap" -i 2 -c loop_video=1 --set-fmt-video=width=720,height=480,pixelformat=YUYV,field=interlaced
v4l2-ctl -d "$out" -o 0 --set-fmt-video-out=width=720,height=480,pixelformat=YUYV,field=interlaced
v4l2-ctl -d "$cap" --get-fmt-video 2>&1 | sed 's/^/@@diag_c cap /'
v4l2-ctl -d "$out" --get-fmt-video-out 2>&1 | sed 's/^/@@diag_c out /'

# loop FILE: streams FILE out of the output node in the background (pid in $loop_pid).
loop() {
	v4l2-ctl -d "$out" -o 0 --stream-out-mmap --stream-from="$1" --stream-loop >/dev/null 2>&1 &
	loop_pid=$!
	sleep 1
}
unloop() {
	kill $loop_pid
	wait $loop_pid 2>/dev/null
}

# The loop pixel by pixel: a known pattern written, one frame captured (after the first few, which
# may predate the output stream), the differing bytes counted with where they lie; with vivid's
# OSD text on (its default, mode 0) and off (mode 2).
for osd in 0 2; do
	v4l2-ctl -d "$cap" -c osd_text_mode=$osd
	loop /data/blurprobe.yuyv
	v4l2-ctl -d "$cap" --stream-mmap --stream-skip=3 --stream-count=1 --stream-to=/tmp/probe.yuyv >/dev/null 2>&1
	unloop
	echo "@@c_probe_$osd.size $(wc -c </tmp/probe.yuyv)"
	cmp -l /data/blurprobe.yuyv /tmp/probe.yuyv 2>/dev/null | awk -v tag="c_probe_$osd" '
		{ o = $1 - 1; r = int(o / 1440); c = int((o % 1440) / 2); n++
		  if (n == 1) { r0 = r; r1 = r; c0 = c; c1 = c }
		  if (r < r0) r0 = r; if (r > r1) r1 = r; if (c < c0) c0 = c; if (c > c1) c1 = c }
		END { printf "@@%s.diff bytes=%d rows=%d-%d cols=%d-%d\n", tag, n, r0, r1, c0, c1 }'
	rm -f /tmp/probe.yuyv
done

# The blur frames, OSD text off; one with it on, to show what the text does to the readings.
for f in sharp g1 g2 g4 d4 d6 d8 osd_g2; do
	case $f in
	osd_*) v4l2-ctl -d "$cap" -c osd_text_mode=0 ;;
	*) v4l2-ctl -d "$cap" -c osd_text_mode=2 ;;
	esac
	loop "/data/blur${f#osd_}.yuyv"
	# Every region searched afresh each frame, as the host reads the same frames (run.sh).
	run c_$f infocus analyze "v4l2:$cap,input=2,format=YUYV,size=720x480" --frames 8 --grid 3x2 \
		--blur-search all
	unloop
done
v4l2-ctl -d "$cap" -c osd_text_mode=0

# d. faults on the webcam input: buffer errors and drops are counted; a disconnect ends the run
v4l2-ctl -d "$cap" -i 0
(sleep 2; v4l2-ctl -d "$cap" -c percentage_of_dropped_buffers=30; sleep 2
	v4l2-ctl -d "$cap" -c percentage_of_dropped_buffers=0
	for i in 1 2 3; do v4l2-ctl -d "$cap" -c inject_v4l2_buf_flag_error=1; sleep 1; done) >/dev/null 2>&1 &
run d_faults infocus record "v4l2:$cap,size=320x180" -o /tmp/rec_faults --seconds 8
wait
rm -rf /tmp/rec_v4l2 /tmp/rec_lc /tmp/rec_faults
# Unplug only once frames are being recorded: infocus takes seconds to start under emulation, and a
# disconnect before it opens the node is undone by vivid as soon as v4l2-ctl closes it.
(for i in $(seq 1 60); do [ -s /tmp/rec_unplug/frames.bin ] && break; sleep 1; done
	sleep 1
	v4l2-ctl -d "$cap" -c disconnect=1 2>&1 | sed "s/^/@@diag_disc /"
	echo "@@diag_disc sent") &
run d_unplug infocus record "v4l2:$cap,size=320x180" -o /tmp/rec_unplug --seconds 12
wait
run d_replay infocus analyze /tmp/rec_unplug --grid 2x2

# g. an unplug mid-run ends the live assistant with the reason; sent once it has printed a state,
# for the same reason as in part d (and last, so no other part sees the disconnected node)
rm -f /tmp/out
(for i in $(seq 1 60); do grep -q '^{' /tmp/out 2>/dev/null && break; sleep 1; done
	v4l2-ctl -d "$cap" -c disconnect=1 2>&1 | sed "s/^/@@diag_gdisc /"
	echo "@@diag_gdisc sent") &
run g_unplug infocus live "v4l2:$cap,size=320x180" --ui json --seconds 30
wait

df -k /tmp | sed "s/^/@@diag /"
echo "@@done"
sync
poweroff -f
