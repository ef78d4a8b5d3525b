#!/usr/bin/env python3
"""Issue 28's targets, frame by frame, from the eval.csv files scripts/evaluate.sh writes.

Usage: scripts/targets-table.py OUT [SETTING]   (SETTING: a setting of the eval runs, default "surfels")

Per frame, against the peers of the same run: near frames need FLIP <= Embree's at 1 sample in at most
1.25 x its time; mid and far frames FLIP <= Embree's at 4 samples in at most Embree's 1-sample time;
every frame holes <= 2 % and bloat <= 10 % of the reference's covered pixels. Prints one markdown row
per scene and path (medians over its frames) and the totals.
"""
import csv
import statistics
import sys
from pathlib import Path

SCENES = ["default", "city", "unique"]
PATHS = ["orbit", "approach", "flythrough"]


def frames_of(table, setting):
    return {int(r["frame"]): r for r in table if r["setting"] == setting}


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    setting = sys.argv[2] if len(sys.argv) == 3 else "surfels"
    print("| scene, path | frames n/m/f | Embree 1: FLIP, ms | Embree 4: FLIP, ms | "
          f"{setting}: FLIP, ms | speed-up vs Embree 1 | holes, bloat (median) | frames meeting the targets |")
    print("| --- | --- | ---: | ---: | ---: | ---: | ---: | --- |")
    totals = {"flip": 0, "time": 0, "coverage": 0, "all": 0, "frames": 0}
    for scene in SCENES:
        for path in PATHS:
            file = out / f"{scene}-{path}" / "eval.csv"
            if not file.exists():
                continue
            table = list(csv.DictReader(file.open()))
            one, four, ours = (frames_of(table, s) for s in ("embree=1", "embree=4", setting))
            if not ours or not one or not four:
                print(f"{file}: needs embree=1, embree=4 and {setting}", file=sys.stderr)
                continue
            met = {"flip": 0, "time": 0, "coverage": 0, "all": 0}
            kinds = {"near": 0, "mid": 0, "far": 0}
            for f, r in ours.items():
                kind = r["kind"]
                kinds[kind] += 1
                near = kind == "near"
                flip_bar = float((one if near else four)[f]["flip"])
                time_bar = float(one[f]["seconds"]) * (1.25 if near else 1.0)
                ok = {"flip": float(r["flip"]) <= flip_bar, "time": float(r["seconds"]) <= time_bar,
                      "coverage": float(r["hole_fraction"]) <= 0.02 and float(r["bloat_fraction"]) <= 0.10}
                ok["all"] = all(ok.values())
                for k, v in ok.items():
                    met[k] += v
            n = len(ours)
            med = lambda rows, key: statistics.median(float(r[key]) for r in rows.values())
            speedup = statistics.median(float(one[f]["seconds"]) / float(r["seconds"]) for f, r in ours.items())
            print(f"| {scene}, {path} | {kinds['near']}/{kinds['mid']}/{kinds['far']} | "
                  f"{med(one, 'flip'):.4f}, {1000 * med(one, 'seconds'):.0f} | "
                  f"{med(four, 'flip'):.4f}, {1000 * med(four, 'seconds'):.0f} | "
                  f"{med(ours, 'flip'):.4f}, {1000 * med(ours, 'seconds'):.1f} | {speedup:.2f}× | "
                  f"{med(ours, 'hole_fraction'):.3f}, {med(ours, 'bloat_fraction'):.3f} | "
                  f"FLIP {met['flip']}/{n}, time {met['time']}/{n}, coverage {met['coverage']}/{n}; "
                  f"all three {met['all']}/{n} |")
            for k in met:
                totals[k] += met[k]
            totals["frames"] += n
    t = totals
    print(f"\ntotal: FLIP {t['flip']}/{t['frames']}, time {t['time']}/{t['frames']}, "
          f"coverage {t['coverage']}/{t['frames']}, all {t['all']}/{t['frames']}")


if __name__ == "__main__":
    main()
