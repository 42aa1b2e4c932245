#!/usr/bin/python3
"""Markdown table of the runs scripts/convergence.py left in a directory:
per algorithm the iterations done, RMSE and relMSE at the end of the equal
time budget, and the fitted slope of log RMSE against log time.

    /usr/bin/python3 scripts/convergence_table.py results/cornell-box
"""

import argparse
import os

from convergence import ALGORITHMS, fitted_slope, read_log


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directories", nargs="+")
    args = parser.parse_args()
    print("| scene | algorithm | seconds | iterations | RMSE | relMSE | slope |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for directory in args.directories:
        scene = os.path.basename(os.path.normpath(directory))
        for algorithm in ALGORITHMS:
            log = os.path.join(directory, algorithm + ".csv")
            if not os.path.exists(log):
                continue
            rows = read_log(log)
            seconds, iterations, rmse, relmse = rows[-1]
            print("| %s | %s | %.1f | %d | %.4g | %.4g | %.2f |"
                  % (scene, algorithm, seconds, iterations, rmse, relmse, fitted_slope(rows)))


if __name__ == "__main__":
    main()
