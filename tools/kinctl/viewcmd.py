# SPDX-License-Identifier: BSD-3-Clause
"""`kinctl view`: the arm drawn from kinctld's setpoints (kinctl.view) in a
live matplotlib window that follows <prefix>SETPOINT on LCM, or with --save
to a file: FILE.png a still, FILE.gif or FILE.mp4 an animation of --duration
seconds of live setpoints, or of a recorded log (--log, a CSV or an LCM
event log).

The frames come from the core's forward kinematics through kinctl-calc
(kinctl.kinematics): --model / --model-file must name the daemon's arm; a
tool position that disagrees with the setpoint's is reported. register()
adds the subcommand to the CLI.
"""
import os
import sys
import time

from kinctl.argtypes import add_command, nonneg, positive, say
from kinctl.view import Sample, Scene, check_save, reach_space, render, samples_from_columns, trail_of, triad_length

EXAMPLE = ("kinctl view                                  # live window (needs a display)\n"
           "  kinctl view --save arm.gif --duration 5        # headless: 5 s of live setpoints\n"
           "  kinctl view --log run.csv --save run.mp4       # a recorded log (CSV or LCM log); mp4 needs ffmpeg\n"
           "  kinctl view --model-file models/panda.cfg --save now.png\n"
           "  kinctl view --model puma560 --zones-file kinctld.cfg --zone sphere:0.5,0.3,0.4,0.1 --save cell.png")


def register(sub, parents):
    """The `view` subcommand on the CLI's subparsers."""
    v = add_command(sub, "view", "draw the arm (skeleton and every link frame) from its setpoints: frontal "
                                 "dimetric, horizontal isometric, orthographic and 3-D views, live or saved",
                    EXAMPLE, parents)
    m = v.add_mutually_exclusive_group()
    m.add_argument("--model", default=None, metavar="NAME",
                   help="the daemon's built-in arm (default puma560, kinctld's default): puma560, panda, rrr3, "
                        "planar2, rb211, rm01")
    m.add_argument("--model-file", default=None, metavar="PATH", help="the daemon's robot description file")
    v.add_argument("--log", default=None, metavar="FILE",
                   help="draw a recorded log (setpoint CSV of kinctl log, or LCM event log) instead of live LCM")
    v.add_argument("--save", default=None, metavar="FILE",
                   help="write FILE.png (a still: the last setpoint), FILE.gif or FILE.mp4 (an animation; mp4 "
                        "needs ffmpeg, which scripts/setup.sh installs) instead of opening a window")
    v.add_argument("--duration", type=positive, default=None, metavar="S",
                   help="live --save: record S seconds of setpoints (default 5 for .gif/.mp4; .png: the next "
                        "setpoint); with --log: only the first S seconds; a window: close it after S seconds")
    v.add_argument("--fps", type=positive, default=25.0, metavar="N", help="frames per second (default 25)")
    v.add_argument("--trail", type=nonneg, default=3.0, metavar="S",
                   help="seconds of tool path drawn behind the tool (default 3; 0: none)")
    v.add_argument("--dpi", type=positive, default=80.0, help="resolution of saved files (default 80)")
    from kinctl.zonedraw import add_options
    add_options(v)
    v.set_defaults(run=cmd_view)


def _warn_mismatch(m, fk):
    """A warning when the drawn tool is m (m) from where the daemon says it is."""
    if m > 1e-6:
        print(f"kinctl view: warning: the drawn tool is {m * 1e3:.3g} mm from the setpoints' tool position: "
              f"the daemon runs another arm than {fk.describe()}? pass its --model or --model-file",
              file=sys.stderr, flush=True)


def record(args, seconds):
    """Setpoints of the daemon spanning `seconds` of trajectory time (cycles
    times the period, as runlog.trajectory_time counts it; a cycle the daemon
    skipped under load is not time the arm moved), or the next one when
    seconds is 0, as logcsv columns."""
    from kinctl.client import Client, DaemonNotFound
    from kinctl.progress import bar
    from kinctl.runlog import setpoint_columns
    got = []
    with Client(url=args.lcm_url, prefix=args.prefix, on_setpoint=got.append) as c:
        c.wait_daemon(args.connect_timeout)
        start = len(got)
        deadline = time.monotonic() + 2 * seconds + args.connect_timeout + 5.0
        period = {}

        def span():
            """Trajectory time from the first recorded setpoint to the last (s)."""
            if len(got) <= start:
                return -1.0
            if "dt" not in period:
                steps = [b.utime - a.utime for a, b in zip(got[start:start + 50], got[start + 1:start + 51])
                         if b.cycle == a.cycle + 1 and b.utime > a.utime]
                if len(steps) < 10 and len(got) - start < 51:
                    return -1.0 if seconds > 0 else 0.0
                import statistics
                period["dt"] = statistics.median(steps) / 1e6 if steps else 1e-3
            return (got[-1].cycle - got[start].cycle) * period["dt"]

        def spanned():
            return span() >= seconds - 1e-9
        with bar(seconds, "recording setpoints", unit="s", show=seconds >= 1.0,
                 bar_format="{desc}: {bar} {n:.1f}/{total:.1f} s") as b:
            while not spanned():
                if time.monotonic() > deadline:
                    raise DaemonNotFound(f"the setpoints stopped coming after {len(got) - start} of them: "
                                       f"did kinctld stop? (kinctl status)")
                time.sleep(0.05)
                b.n = min(seconds, max(0.0, span()))
                b.refresh()
        sps = got[start:]
    return setpoint_columns(sps)


def zones_of(args, fk, q):
    """The zones and the moving link volumes the options ask for (the volumes
    whenever --model or --model-file names the arm, unless --no-volumes)."""
    from kinctl.zonedraw import for_arm
    return for_arm(fk, q, args.zones_file, args.zone,
                   volumes=bool(args.model or args.model_file) and not args.no_volumes)


def cmd_view(args):
    from kinctl.kinematics import ArmFK
    ext = check_save(args.save) if args.save else None
    if args.log and not args.save:
        raise ValueError("--log draws to a file: add --save FILE.gif, .mp4 or .png (to watch an LCM log in "
                         "the window, play it with lcm-logplayer and run kinctl view)")
    with ArmFK(model=args.model, model_file=args.model_file) as fk:
        # Bad --zone or --zones-file: exit 2 before anything is recorded.
        zones_of(args, fk, [0.0] * fk.n_joints)
        if args.log:
            from kinctl.runlog import read_run
            cols, _ = read_run(args.log, prefix=args.prefix, progress=True)
            title = f"{os.path.basename(args.log)}: "
        elif args.save:
            seconds = args.duration if args.duration is not None else (5.0 if ext != ".png" else 0.0)
            cols = record(args, seconds)
            title = f"kinctld ({fk.describe().lstrip('-')}): "
        else:
            return live(args, fk)
        samples = samples_from_columns(cols, args.fps, args.duration)
        if len(samples[0].q) != fk.n_joints:
            raise ValueError(f"the setpoints have {len(samples[0].q)} joints, {fk.describe()} has {fk.n_joints}: "
                             f"pass the daemon's --model or --model-file")
        zones, volumes = zones_of(args, fk, samples[0].q)
        info = render(samples, args.save, fk, fps=args.fps, trail=args.trail, dpi=args.dpi, title=title,
                      progress=True, zones=zones, volumes=volumes)
        _warn_mismatch(info["fk_mismatch_m"], fk)
        if info["frames"] == 1:
            say(f"view: {args.save} (1 frame, {info['size'][0]}x{info['size'][1]}, the setpoint of cycle "
                f"{samples[-1].cycle})")
        else:
            say(f"view: {args.save} ({info['frames']} frames, {info['size'][0]}x{info['size'][1]}, "
                f"{samples[-1].t - samples[0].t:.2f} s of setpoints)")
    return 0


def live(args, fk):
    """A window following the daemon's setpoints until it is closed."""
    import matplotlib
    if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY") and sys.platform != "darwin":
        raise ValueError("no display for a window ($DISPLAY is not set): save to a file instead, e.g. "
                         "kinctl view --save arm.gif --duration 5")
    import matplotlib.pyplot as plt
    if matplotlib.get_backend().lower() == "agg":
        raise ValueError("matplotlib has no interactive backend here (install python3-tk or PyQt), or use "
                         "--save arm.gif")
    from matplotlib import animation
    from kinctl.client import Client

    with Client(url=args.lcm_url, prefix=args.prefix) as c:
        sp = c.wait_daemon(args.connect_timeout)
        if sp.n != fk.n_joints:
            raise ValueError(f"the daemon's setpoints have {sp.n} joints, {fk.describe()} has {fk.n_joints}: "
                             f"pass the daemon's --model or --model-file")
        pose0 = fk.frames(list(sp.q[:sp.n]))
        fig = plt.figure(figsize=(12, 9.5))
        bounds, reachable = reach_space(pose0)
        zones, volumes = zones_of(args, fk, list(sp.q[:sp.n]))
        from kinctl.zonedraw import zone_shapes
        scene = Scene(fig, bounds, triad_length(pose0), zone_shapes(zones, bounds),
                      f"kinctld live ({fk.describe().lstrip('-')})", points=reachable, status_in_axes=True,
                      volumes=volumes)
        history = []
        state = {"last_cycle": None, "warned": False, "drawn": 0}

        def frame(_):
            s = c.setpoint
            if s is None or s.cycle == state["last_cycle"]:
                return []
            state["last_cycle"] = s.cycle
            # Live, time is the daemon's clock at the cycle (utime).
            smp = Sample((s.utime - sp.utime) / 1e6, s.cycle, s.goal_id, s.state, list(s.q[:s.n]),
                         tuple(s.position))
            history.append(smp)
            while history and history[0].t < smp.t - args.trail - 1.0:
                history.pop(0)
            pose = fk.frames(smp.q)
            if not state["warned"]:
                import numpy as np
                _warn_mismatch(float(np.linalg.norm(pose[2][:3, 3] - np.asarray(smp.tool))), fk)
                state["warned"] = True
            state["drawn"] += 1
            return scene.update(pose, smp, trail_of(history, len(history) - 1, args.trail))

        anim = animation.FuncAnimation(fig, frame, interval=1000.0 / args.fps, blit=True,
                                       cache_frame_data=False)
        fig._kinctl_anim = anim  # keep a reference while the window is open
        if args.duration:
            timer = fig.canvas.new_timer(interval=int(args.duration * 1000))
            timer.single_shot = True

            def close():
                anim.event_source.stop()
                plt.close(fig)
            timer.add_callback(close)
            timer.start()
        plt.show()
    say(f"view: window closed after {len(history) and history[-1].t:.2f} s of setpoints, "
        f"{state['drawn']} frames drawn")
    return 0
