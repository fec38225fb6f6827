#!/usr/bin/python3
"""Leader election from Python: find the first step with two leaders, look at how it came about.

    PYTHONPATH=build/python /usr/bin/python3 docs/examples/leader_election.py --out /tmp/example

Runs scenarios/leader_election.toml (a buggy election: two leaders can be elected a hop apart),
stops at the first match of its `two_leaders` watchpoint, seeks to that step, plots isLeader of
the matched group's modules over the steps up to it, and saves the 3D view with the group lit.
CI runs this script (ctest: Python.ExampleLeaderElection).
"""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402

import dwatch  # noqa: E402

def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("example"), help="folder for the pictures")
    # The scenario the package ships: the example runs outside a checkout too (a wheel installed).
    parser.add_argument("--scenario", default=str(dwatch.scenario_path("leader_election.toml")))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    session = dwatch.Session(args.scenario, threads=2)
    answer = session.run()  # the watchpoint's action is `pause`: the run stops at its first match
    paused = answer["paused"]
    if paused is None:
        raise SystemExit("no two leaders in this run")
    matches = session.matches("two_leaders")
    t, group = int(matches.t[0]), [int(m) for m in matches.slots[0]]
    print(f"two leaders at step {t}: modules {dict(zip(matches.slot_names, group))} "
          f"({paused['matches']} matches at that step; found at step {int(matches.detected[0])})")

    # How isLeader evolved on the group's modules, from step 0 to ten steps past the match (the
    # watchpoint only logs from here on, so the run goes past its next matches).
    session.action("two_leaders", "log")
    last = t + 10
    session.run(last)
    session.seek(t)
    figure, rows = plt.subplots(len(group), 1, sharex=True, figsize=(7, 1.2 + 1.1 * len(group)), dpi=120)
    for axes, slot, module in zip(rows, matches.slot_names, group):
        series = session.series(module, "isLeader", 0, last)
        axes.step(range(last + 1), series, where="post", linewidth=2, color="#2f6db5")
        axes.axvline(t, color="#d71c29", linestyle="--")
        axes.set(ylim=(-0.2, 1.2), yticks=[0, 1])
        axes.set_ylabel(f"{slot}: {module}", rotation=0, ha="right", va="center")
    rows[0].set_title(f"isLeader of the matched group's modules (match at step {t}, dashed)")
    rows[-1].set_xlabel("step")
    rows[-1].xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
    figure.tight_layout()
    plot = args.out / "is_leader.png"
    figure.savefig(plot)

    view = args.out / "view.png"
    plt.imsave(view, session.render(1280, 720))
    print(f"wrote {plot} and {view}; the state hash at step {t} is {session.hash()}")


if __name__ == "__main__":
    main()
