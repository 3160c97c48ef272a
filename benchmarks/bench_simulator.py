"""Print the simulator's speed and accuracy next to solve_ivp (DOP853, rtol 1e-12, terminal events).

    .venv/bin/python benchmarks/bench_simulator.py [n_impacts] [n_impacts_ivp] [n_flights]

The workflow target `snakemake --cores 2 bench` runs the same and saves results/bench/simulator.nc.
"""
import sys

from vibroimpact.benchmarks.bench import report, simulator_benchmark

if __name__ == "__main__":
    args = [int(a) for a in sys.argv[1:]] + [1_000_000, 2000, 200][len(sys.argv) - 1:]
    print(report(simulator_benchmark(*args[:3])))
