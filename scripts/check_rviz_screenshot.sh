#!/bin/bash
# A check with a real client: runs the demo with rviz under Xvfb, takes a screenshot and asserts
# that the soft block is drawn (its pixels differ from rviz's background in the expected region).
# Needs Debian's rviz, xvfb and imagemagick (scripts/install_dependencies.sh installs them).
#   scripts/check_rviz_screenshot.sh [screenshot.png]
# Exit 0 when the block is seen, 1 otherwise (with one line saying what was seen).
# (no set -u: the catkin setup scripts read unset variables)
shot="${1:-/tmp/msm_sim_rviz.png}"
export PATH=/usr/bin:/bin:$PATH
root="$(cd "$(dirname "$0")/.." && pwd)"
if ! rospack find msm_sim >/dev/null 2>&1; then
  # shellcheck disable=SC1091
  source "$root/build/ws/devel/setup.bash" || { echo "check_rviz_screenshot: build first (make build)"; exit 1; }
fi
display=":$((90 + RANDOM % 9))"
Xvfb "$display" -screen 0 800x600x24 -nolisten tcp >/dev/null 2>&1 &
xvfb=$!
trap 'kill $launch $xvfb 2>/dev/null; wait 2>/dev/null' EXIT
export DISPLAY="$display"
roslaunch msm_sim demo.launch rviz:=true duration:=30 >/tmp/msm_sim_rviz_launch.log 2>&1 &
launch=$!
# rviz needs a few seconds to start and the finger a few more to press (the demo presses at 1-3 s).
sleep 14
import -window root "$shot" || { echo "check_rviz_screenshot: no screenshot"; exit 1; }
# Share of pixels in the centre of the view that are not rviz's background (48, 48, 48) and not
# grey grid lines: the block is drawn in strain colours from white to red and blue.
share=$(convert "$shot" -crop 400x300+200+150 +repage -fx \
  "(abs(r-g)>0.08 || abs(g-b)>0.08 || (r>0.6 && g>0.6 && b>0.6)) ? 1 : 0" \
  -format "%[fx:mean]" info:)
echo "check_rviz_screenshot: ${share} of the central pixels show the block (screenshot ${shot})"
awk -v s="$share" 'BEGIN { exit !(s > 0.05) }'
