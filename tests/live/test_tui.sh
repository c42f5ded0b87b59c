#!/usr/bin/env bash
# The terminal view as a person uses it: `infocus live` on the simulated camera in tmux (100×30
# and 80×24), looked at through capture-pane. The meter and the grid show; a finds focus at the
# sim's 1 m; ←/→ move the lens through focus and past it, and the cue shows; r clears it; g
# cycles the grid; q exits 0 and gives the terminal back, as do SIGTERM and Ctrl-C. With lens
# data (a scripted pipeline, tui_fake) the DoF, blur in µm, diffraction and tilt lines show,
# Shift moves ten steps and a control's error is shown.
# Usage: test_tui.sh PATH_TO_INFOCUS HAVE_TUI(true|false) [PATH_TO_TUI_FAKE]
set -u
bin=${1:?path to infocus}
if [[ ${2:-true} != true ]]; then
	echo "SKIP: this build has no terminal view (ncursesw not found)"
	exit 77
fi
if ! command -v tmux >/dev/null; then
	echo "SKIP: tmux is missing"
	exit 77
fi
tmp=$(mktemp -d)
export LC_ALL=C.UTF-8
# A tmux server of our own (its own socket, no config), so nothing of the user's is touched.
tm() { tmux -S "$tmp/tmux.sock" -f /dev/null "$@"; }
trap 'tm kill-server 2>/dev/null; rm -rf "$tmp"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*"; fail=$((fail + 1)); }
source_string='sim:focal=16mm,fnumber=1.4,distance=1m,focus=0.5m'

# start NAME COLSxLINES: infocus live in a detached session; its exit status lands in
# $tmp/NAME.exit, then the shell prints a marker and waits, so the pane outlives the view.
start() {
	local name=$1 cols=${2%x*} lines=${2#*x}
	tm new-session -d -s "$name" -x "$cols" -y "$lines" \
		"echo \$\$ > $tmp/$name.pid; TERM=tmux-256color $bin live '$source_string' --ui tui; \
		echo EXIT=\$? > $tmp/$name.exit; echo VIEW-ENDED; sleep 120"
}
screen() { tm capture-pane -p -t "$1"; }
# wait_for NAME SECONDS REGEX: polls the pane until a line matches; 1 on time-out.
wait_for() {
	local name=$1 secs=$2 re=$3 i
	for ((i = 0; i < secs * 5; i++)); do
		screen "$name" | grep -qE -- "$re" && return 0
		sleep 0.2
	done
	return 1
}
# check_view NAME COLS LINES: the meter (big digits and bar, the peak mark, the trend), the
# history, the grid (9 rows of labelled, coloured cells) and the help line are on screen.
check_view() {
	local name=$1 cols=$2 lines=$3 s
	s=$(screen "$name")
	[[ $(wc -l <<<"$s") -eq $lines ]] && ok || bad "$name: the pane is not ${lines} lines"
	[[ $(wc -L <<<"$s") -le $cols ]] && ok || bad "$name: a line is wider than $cols columns"
	[[ $(sed -n 2p <<<"$s") =~ █.*█{20} ]] && ok || bad "$name: no meter bar on line 2"
	grep -q 'peak┘' <<<"$s" && ok || bad "$name: no peak mark under the meter"
	grep -qE '(sharper|worse|steady)   score ' <<<"$s" && ok || bad "$name: no trend word"
	grep -qE '[▁▂▃▄▅▆▇█]{10}' <<<"$s" && ok || bad "$name: no history sparkline"
	grep -q 'regions 16×9' <<<"$s" && ok || bad "$name: no grid legend"
	local cells
	cells=$(sed -n '/regions 16×9/,/^ lens /p' <<<"$s" | grep -cE '^ *(([0-9]+(\.[0-9])?|·)( +|$)){16}$')
	[[ $cells -eq 9 ]] && ok || bad "$name: $cells grid rows of 16 cells, want 9"
	# Colour: the heat map paints cell backgrounds.
	tm capture-pane -e -p -t "$name" | grep -qE $'\e''\[[0-9;]*(4[0-7]|48;5;[0-9]+)m' &&
		ok || bad "$name: no coloured cells"
	grep -q '←/→ focus  a autofocus  c continuous  r reset  g grid  p peaking  q quit' <<<"$s" &&
		ok || bad "$name: no help line"
	grep -qE "^ sim:focal=.*latency [0-9.]+/[0-9.]+ ms" <<<"$s" && ok ||
		bad "$name: no title with the latency"
}
# check_exit NAME: the view exited 0 and left the alternate screen: the shell's marker shows and
# nothing of the view remains.
check_exit() {
	local name=$1 i
	for ((i = 0; i < 50; i++)); do
		[[ -s $tmp/$name.exit ]] && break
		sleep 0.2
	done
	[[ $(cat "$tmp/$name.exit" 2>/dev/null) == EXIT=0 ]] && ok ||
		bad "$name: exit $(cat "$tmp/$name.exit" 2>/dev/null || echo '(none)'), want EXIT=0"
	wait_for "$name" 5 '^VIEW-ENDED' && ok || bad "$name: the shell's output does not show"
	[[ $(tm display -p -t "$name" '#{alternate_on}') == 0 ]] && ok ||
		bad "$name: still on the alternate screen"
	screen "$name" | grep -qE 'peak┘|a autofocus' && bad "$name: the view is still drawn" || ok
}

# 100×30: the whole session.
start wide 100x30
if wait_for wide 30 'peak┘' && wait_for wide 20 'regions 16×9'; then
	sleep 1
	check_view wide 100 30
	echo "--- 100×30, before autofocus:"
	screen wide
	# The sim's plane is 1 m away: autofocus ends with the lens focused there. (Asked first, on a
	# lens at rest.)
	tm send-keys -t wide a
	found="" d=""
	for ((i = 0; i < 150; i++)); do
		d=$(screen wide | grep -oE 'in focus at [0-9.]+ m?m' | head -1)
		if [[ -n $d ]] && ! screen wide | grep -q 'autofocus…'; then
			metres=$(awk '{v=$4; if ($5=="mm") v/=1000; print v}' <<<"$d")
			if awk -v m="$metres" 'BEGIN{exit !(m >= 0.95 && m <= 1.05)}'; then
				found=$d
				break
			fi
		fi
		sleep 0.2
	done
	[[ -n $found ]] && ok || bad "wide: after a, no 'in focus at' 0.95–1.05 m (last: '$d')"
	echo "--- 100×30, after autofocus ($found):"
	screen wide
	# Three steps back from focus; r forgets the peak there (and any cue the sweep left); six
	# steps forward climb through focus and fall past it, and the cue shows.
	lens0=$(screen wide | grep -oE '^ lens [^ ]+ [^ ]+')
	for k in Left Left Left; do
		tm send-keys -t wide $k
		sleep 0.5
	done
	[[ $(screen wide | grep -oE '^ lens [^ ]+ [^ ]+') != "$lens0" ]] && ok ||
		bad "wide: ← left the lens at '$lens0'"
	sleep 1
	tm send-keys -t wide r
	for ((i = 0; i < 50; i++)); do
		screen wide | grep -q '◀ past the peak' || break
		sleep 0.2
	done
	screen wide | grep -q '◀ past the peak' && bad "wide: r left the past-peak cue" || ok
	for k in Right Right Right Right Right Right; do
		tm send-keys -t wide $k
		sleep 0.7
	done
	wait_for wide 10 '◀ past the peak — back up' && ok || bad "wide: no past-peak cue past focus"
	echo "--- 100×30, three steps past focus:"
	screen wide
	tm send-keys -t wide g
	wait_for wide 10 'regions 8×6' && ok || bad "wide: g did not change the grid to 8×6"
	tm send-keys -t wide g
	wait_for wide 10 'regions 4×3' && ok || bad "wide: g did not change the grid to 4×3"
	echo "--- 100×30, grid 4×3:"
	screen wide
	tm send-keys -t wide g
	wait_for wide 10 'regions 16×9' && ok || bad "wide: g did not bring the grid back to 16×9"
	tm send-keys -t wide q
	check_exit wide
else
	bad "wide: the meter did not show within 50 s"
	screen wide
fi

# 80×24: the view fits the smallest terminal; SIGTERM ends it as cleanly as q.
start small 80x24
if wait_for small 30 'peak┘' && wait_for small 20 'regions 16×9'; then
	sleep 1
	check_view small 80 24
	echo "--- 80×24:"
	screen small
	pid=$(pgrep -P "$(cat "$tmp/small.pid")" -x infocus)
	if [[ -n $pid ]]; then
		kill -TERM "$pid"
		check_exit small
	else
		bad "small: cannot find the infocus process"
	fi
else
	bad "small: the meter did not show within 50 s"
	screen small
fi

# Ctrl-C (SIGINT from the terminal) ends it as cleanly too.
start ctrlc 80x24
if wait_for ctrlc 30 'peak┘'; then
	tm send-keys -t ctrlc C-c
	check_exit ctrlc
else
	bad "ctrlc: the meter did not show within 30 s"
fi

# With lens data: the optics lines, from the scripted pipeline (lens at 2 dpt over a plane at 1 m).
fake=${3:-}
if [[ -n $fake ]]; then
	tm new-session -d -s lens -x 100 -y 30 "TERM=tmux-256color $fake 60; echo EXIT=\$? > $tmp/lens.exit; \
		echo VIEW-ENDED; sleep 120"
	if wait_for lens 10 'tilt 3.2°'; then
		s=$(screen lens)
		grep -q '^ lens 2.00 D   in focus at 500 mm$' <<<"$s" && ok || bad "lens: no lens line"
		grep -q '^ DoF 483 mm – 518 mm$' <<<"$s" && ok || bad "lens: no DoF line"
		grep -qE '^ blur [0-9.]+ px = [0-9.]+ µm  CoC 2.0 px  diffraction 1.3 px$' <<<"$s" && ok ||
			bad "lens: no blur line against CoC and diffraction"
		grep -qE '^ [0-9]+ of 124 regions within CoC   tilt 3.2°   in focus along \(960, 0\)–\(980, 1080\)$' \
			<<<"$s" && ok || bad "lens: no regions and tilt line"
		echo "--- 100×30, with lens data (scripted):"
		echo "$s"
		# Shift moves ten steps (0.05 dpt each here); a control's error lands on the status line.
		tm send-keys -t lens S-Right
		wait_for lens 5 '^ lens 2.50 D' && ok || bad "lens: Shift+→ did not move ten steps"
		tm send-keys -t lens S-Left S-Left S-Left S-Left S-Left S-Left
		wait_for lens 5 '^ the lens is at the end of its range' && ok ||
			bad "lens: a control's error is not on the status line"
		tm send-keys -t lens q
		check_exit lens
	else
		bad "lens: the scripted view did not show"
		screen lens
	fi
fi

echo "tui: $pass passed, $fail failed"
[[ $fail -eq 0 ]]
