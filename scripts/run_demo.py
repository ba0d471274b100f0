#!/usr/bin/env python3
"""Runs launch/demo.launch until its summary is done, then ends the launch cleanly.

Usage: run_demo.py [ARG:=VALUE ...]   (demo.launch's arguments: duration, rviz, output_dir)

`make demo` runs this. roslaunch ends a launch on its own only when a `required` node exits,
and then reports that node as died; here the launch is ended through the roslaunch API once
demo_summary has finished. Exit code: demo_summary's (0 after a summary), 1 when the simulation
node died or the summary did not finish.
"""
import sys
import time

import roslaunch
import roslaunch.parent
import roslaunch.pmon
import roslaunch.rlutil


class SummaryWatcher(roslaunch.pmon.ProcessListener):
    """Remembers how demo_summary and msm_sim ended (process names are `<node>-<n>`)."""

    def __init__(self):
        self.summary_exit = None
        self.simulation_died = False

    def process_died(self, name, exit_code):
        if name.startswith("demo_summary-"):
            self.summary_exit = exit_code
        elif name.startswith("msm_sim-"):
            self.simulation_died = True


def main(arguments):
    launch_file = roslaunch.rlutil.resolve_launch_arguments(["msm_sim", "demo.launch"])[0]
    uuid = roslaunch.rlutil.get_or_generate_uuid(None, False)
    roslaunch.configure_logging(uuid)
    watcher = SummaryWatcher()
    parent = roslaunch.parent.ROSLaunchParent(
        uuid, [(launch_file, arguments)], process_listeners=[watcher])
    parent.start()
    try:
        while (watcher.summary_exit is None and not watcher.simulation_died and
               not parent.runner.pm.is_shutdown):
            parent.spin_once()
            time.sleep(0.1)
        # Decided before the shutdown, which stops every node on purpose.
        simulation_died, summary_exit = watcher.simulation_died, watcher.summary_exit
    finally:
        parent.shutdown()
    if simulation_died:
        print("run_demo: msm_sim_node ended before the summary", file=sys.stderr)
        return 1
    return 0 if summary_exit == 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
