#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Optimise a graph file as `graphslam optimize FILE` does, and save the result.

Prints the progress of every iteration (the callback), the result, and the marginal
covariance of the last pose; writes FILE's optimised graph to OUT when given.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/optimize_dataset.py \
        ../shared/datasets/intel.g2o [OUT.g2o]
"""
import sys

import numpy as np

import graphslam


def main():
    path = sys.argv[1]
    graph = graphslam.load(path)
    print(f"{path}: {graph.num_vertices} vertices, {graph.num_edges} edges ({graph.format})")

    def progress(stats):
        print(f"iter {stats['iteration']:3d}  chi2 {stats['chi2']:.10g}  step {stats['step_norm']:.3e}")

    result = graphslam.optimize(graph, callback=progress)
    for line in result.initialization:
        print("initialisation:", line)
    print(f"{result.status}: chi2 {result.initial_chi2:.10g} -> {result.final_chi2:.10g}, "
          f"{result.iterations} iterations, {result.time['total']:.3f} s ({result.linear_solver})")

    tag = "VERTEX_SE2" if "VERTEX_SE2" in graph.counts() else "VERTEX_SE3:QUAT"
    ids, _ = graph.estimates(tag)
    last = int(ids[-1])
    cov = graphslam.marginals(graph, ids=[last])[last]
    print(f"marginal covariance of vertex {last} (diagonal):", np.array2string(np.diag(cov), precision=4))
    if len(sys.argv) > 2:
        graph.save(sys.argv[2])
        print("wrote", sys.argv[2])


if __name__ == "__main__":
    main()
