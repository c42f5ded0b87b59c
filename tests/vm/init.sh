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
ip link set lo up  # the web face of part i listens on loopback

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
# vimc's capture nodes and lens sub-devices, by name (part i)
for n in /sys/class/video4linux/*; do
	case $(cat "$n/name") in
	"Raw Capture 0") raw0=/dev/$(basename "$n") ;;
	"Lens A") lensA=/dev/$(basename "$n") ;;
	"Lens B") lensB=/dev/$(basename "$n") ;;
	esac
done
echo "@@vimc raw0=$raw0 lensA=$lensA lensB=$lensB"
v4l2-ctl -d "$cap" -L 2>&1 | sed 's/^/@@diag /'

echo "@@time a $(cut -d" " -f1 /proc/uptime)"
# a. discovery
run a infocus devices --json
run a_text infocus devices
run a_unit test_drivers_v4l2_device

echo "@@time b $(cut -d" " -f1 /proc/uptime)"
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

echo "@@time e $(cut -d" " -f1 /proc/uptime)"
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

echo "@@time f $(cut -d" " -f1 /proc/uptime)"
# f. focus sweep: a sweep where the camera has a focus control, a refusal where it has none
run f_v4l2 infocus sweep "v4l2:$cap,size=320x180" --steps 3 --refine 0 --grid 2x2 --no-blur --json
run f_lc infocus sweep libcamera:0 --steps 3 --refine 0 --grid 2x2 --no-blur --json

echo "@@time g $(cut -d" " -f1 /proc/uptime)"
# g. the live assistant's JSON face for five seconds on each camera (vivid on its webcam input).
# Small modes: under emulation vimc's 1920x1080 default gives one analysed frame in 1.5 s. vimc
# takes only widths and heights that are multiples of 6 (its scaler triples the sensor's size).
run g_v4l2 infocus live "v4l2:$cap,size=320x180" --ui json --seconds 5
run g_lc infocus live libcamera:0,size=720x480 --ui json --seconds 5

echo "@@time i $(cut -d" " -f1 /proc/uptime)"
# i. lens sub-devices: vimc's sensors have ancillary links to "Lens A" and "Lens B"; the live
# assistant's web face steps the lens three times by 3 and the lens node is read back after each
# step (vimc's image does not change with focus: only the control path is tested)
for m in /dev/media*; do media-ctl -d "$m" -p 2>/dev/null | grep -q "Sensor A" && vimcmc=$m; done
media-ctl -d "$vimcmc" -p 2>&1 | grep -A4 "Lens\|entity.*Sensor" | sed 's/^/@@diag_i /'
# step_lens TAG LENS: once live has printed a state, POST /control {"focus_step": 3} three times,
# reading LENS back after each, then stops live (SIGTERM: exit 0)
step_lens() {
	for i in $(seq 1 90); do
		grep -q '^{' /tmp/out 2>/dev/null && break
		[ $i -gt 3 ] && ! pidof infocus.bin >/dev/null && return
		sleep 1
	done
	echo "@@$1.before $(v4l2-ctl -d "$2" -C focus_absolute 2>&1)"
	for k in 1 2 3; do
		reply=$(wget -q -O - --header 'Content-Type: application/json' \
			--post-data '{"focus_step": 3}' http://127.0.0.1:8080/control 2>&1)
		sleep 2
		echo "@@$1.step $k $(v4l2-ctl -d "$2" -C focus_absolute 2>&1) reply=$reply"
	done
	sleep 2
	pid=$(pidof infocus.bin) && kill $pid
}
# Raw Capture 0 streams Sensor A's Bayer frames once the sensor's format matches its other
# consumer, Debayer A (SRGGB8 at 640x480, its default sink format): what libcamera would set up
media-ctl -d "$vimcmc" -V '"Sensor A":0[fmt:SRGGB8_1X8/640x480]' 2>&1 | sed 's/^/@@diag_i /'
rm -f /tmp/out
step_lens i_v4l2 "$lensA" &
run i_v4l2 infocus live "v4l2:$raw0,format=SRGGB8,size=640x480" --ui json,web --listen 127.0.0.1:8080 --seconds 60
wait
rm -f /tmp/out
v4l2-ctl -d "$lensB" -c focus_absolute=100  # part f's sweep left it at an end
step_lens i_lc "$lensB" &
run i_lc infocus live libcamera:0,size=720x480 --ui json,web --listen 127.0.0.1:8080 --seconds 60
wait

echo "@@time j $(cut -d" " -f1 /proc/uptime)"
# j. faults injected through vivid's controls on its webcam input (S-Video for the signal): each
# under the live assistant and under record; a recording is read back to count its frames
v4l2-ctl -d "$cap" -i 0
echo "@@j_cap $cap"
# wait_started: until live has printed a state or record has written a frame
wait_started() {
	for i in $(seq 1 60); do
		grep -q '^{' /tmp/out 2>/dev/null && break
		[ -s /tmp/rec_j/frames.bin ] && sleep 1 && break
		sleep 1
	done
}
# fault NAME WHEN RESET CONTROLS...: runs live and record with the controls set before the run
# (WHEN=before) or once it has started (WHEN=during: 3 times 0.5 s apart, for buttons), and
# the control RESET (or -) set after each run; source and limits from $jsrc, $jlive and $jrec
fault() {
	name=$1 when=$2 reset=$3
	shift 3
	for cmd in live rec; do
		rm -rf /tmp/out /tmp/rec_j
		if [ "$when" = before ]; then
			for c in "$@"; do v4l2-ctl -d "$cap" -c "$c" 2>&1 | sed "s/^/@@diag_j /"; done
		else
			(wait_started
				for k in 1 2 3; do
					for c in "$@"; do v4l2-ctl -d "$cap" -c "$c" 2>&1 | sed "s/^/@@diag_j /"; done
					sleep 0.5
				done) &
		fi
		if [ $cmd = live ]; then
			run j_${name}_live timeout 60 infocus live "$jsrc" --ui json $jlive
		else
			run j_${name}_rec timeout 60 infocus record "$jsrc" -o /tmp/rec_j $jrec
			if [ -d /tmp/rec_j ]; then
				run j_${name}_replay timeout 60 infocus analyze /tmp/rec_j --grid 1x1
			fi
		fi
		wait
		[ "$reset" = - ] || v4l2-ctl -d "$cap" -c "$reset"
	done
}
jsrc="v4l2:$cap,size=320x180" jlive="--seconds 3" jrec="--seconds 3"
fault none before - # what the emulated machine drops by itself
fault streamon before - inject_vidioc_streamon_error=1
fault qbuf during - inject_vidioc_qbuf_error=1
fault drop10 before percentage_of_dropped_buffers=0 percentage_of_dropped_buffers=10
fault drop50 before percentage_of_dropped_buffers=0 percentage_of_dropped_buffers=50
# a format change refused: another program streams from the node, so S_FMT is busy
for cmd in live rec; do
	v4l2-ctl -d "$cap" --set-fmt-video=width=640,height=360 --stream-mmap --stream-count=150 \
		>/dev/null 2>&1 &
	busy=$!
	sleep 2
	echo "@@diag_j busy $cmd"
	if [ $cmd = live ]; then
		run j_busy_live timeout 30 infocus live "v4l2:$cap,size=320x180" --ui json --seconds 4
	else
		rm -rf /tmp/rec_j
		run j_busy_rec timeout 30 infocus record "v4l2:$cap,size=320x180" -o /tmp/rec_j --seconds 4
	fi
	kill $busy 2>/dev/null
	wait $busy
done
echo "@@diag_j unoffered"
run j_unoffered_live timeout 30 infocus live "v4l2:$cap,format=MJPG" --ui json --seconds 4
rm -rf /tmp/rec_j
run j_unoffered_rec timeout 30 infocus record "v4l2:$cap,format=MJPG" -o /tmp/rec_j --seconds 3
# HDMI (input 3): the reduced frame rate (1000/1001), then no signal
echo "@@diag_j hdmi"
v4l2-ctl -d "$cap" -i 3
# 1280x720 frames: the recordings are kept short (tmpfs in 1 GB)
jsrc="v4l2:$cap,input=3" jlive="--seconds 3" jrec="--frames 30"
v4l2-ctl -d "$cap" --get-fmt-video --get-parm 2>&1 | sed 's/^/@@diag_j hdmi /'
v4l2-ctl -d "$cap" -c reduced_framerate=1
v4l2-ctl -d "$cap" --get-parm 2>&1 | sed 's/^/@@diag_j reduced /'
fault reduced before - reduced_framerate=1
v4l2-ctl -d "$cap" -c reduced_framerate=0
jlive="--seconds 12" jrec="--seconds 12"
fault nosignal during dv_timings_signal_mode=0 dv_timings_signal_mode=1
v4l2-ctl -d "$cap" -i 0
rm -rf /tmp/out /tmp/rec_j

echo "@@time c $(cut -d" " -f1 /proc/uptime)"
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

echo "@@time d $(cut -d" " -f1 /proc/uptime)"
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
echo "@@time end $(cut -d" " -f1 /proc/uptime)"
echo "@@done"
sync
poweroff -f
