"""msm_lab's commands as functions: msm_sim.lab.<command>(**options) returns the dict that
`msm_lab <command> ... --json` prints (docs/lab.md).

Options take the command line's names with underscores for dashes (force_ratio for
--force-ratio); a list or tuple gives several values (size=[0.02, 0.01, 0.01]), True a bare flag
(self_calibrate=True; False leaves it out), and a bool for an on/off option reads as on or off
(antialias=False). The command runs in this process, through the same C++ function as the
executable, with the GIL released. Bad options raise ValueError and a failed experiment
RuntimeError, both carrying the line msm_lab writes to stderr.
"""
import json

from msm_sim import _core

COMMANDS = ("compression", "deflection", "poisson-sweep", "build", "slide", "realtime",
            "indent", "fit", "grip", "grasp", "material")
# The options that are flags on the command line (given bare, without a value).
FLAGS = {"self_calibrate", "free_face_bending"}


def arguments(command, options):
    """The msm_lab command line (without the program name) for `command` and `options`."""
    if command not in COMMANDS:
        raise ValueError("unknown msm_lab command '%s'" % command)
    args = [command]
    for name, value in options.items():
        if name == "json":
            raise ValueError("json: msm_sim.lab always asks for --json")
        flag = "--" + name.replace("_", "-")
        if hasattr(value, "tolist"):  # a numpy array or scalar
            value = value.tolist()
        if isinstance(value, bool):
            if name in FLAGS:
                args += [flag] if value else []
            else:
                args += [flag, "on" if value else "off"]
        elif isinstance(value, (list, tuple)):
            args += [flag] + [_text(v) for v in value]
        else:
            args += [flag, _text(value)]
    return args + ["--json"]


def _text(value):
    # repr gives the shortest text that reads back as the same double.
    return repr(float(value)) if isinstance(value, float) else str(value)


def run(command, **options):
    """Runs `msm_lab command --option value ... --json` in this process; returns its dict."""
    code, out, err = _core.run_lab(arguments(command, options))
    message = err.strip().splitlines()[-1] if err.strip() else "msm_lab %s failed" % command
    if code == 2:
        raise ValueError(message)
    if code != 0:
        raise RuntimeError(message)
    return json.loads(out)


def _command(command):
    def run_command(**options):
        return run(command, **options)
    run_command.__name__ = command.replace("-", "_")
    run_command.__doc__ = ("`msm_lab %s ... --json` as a dict; options as in "
                           "`msm_lab %s --help`, with underscores." % (command, command))
    return run_command


for _name in COMMANDS:
    globals()[_name.replace("-", "_")] = _command(_name)
del _name
