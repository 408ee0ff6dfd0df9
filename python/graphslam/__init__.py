# SPDX-License-Identifier: MIT
"""graphslam: graph-based SLAM from Python.

The C++ library's Python binding (docs/PYTHON.md lists the API with an example each):

    import graphslam
    g = graphslam.load("intel.g2o")            # .g2o 2D/3D, TORO, iSAM, .npz
    result = graphslam.optimize(g)             # as `graphslam optimize intel.g2o`
    ids, poses = g.estimates("VERTEX_SE2")     # int64 (N,), float64 (N, 3)
    ape = graphslam.eval.ape(reference, g.estimates("VERTEX_SE2")[1])

Graphs are built from .g2o tags (graphslam.vertex_tags(), graphslam.edge_tags()); values
are numpy arrays, checked before they reach the library (ValueError for wrong shapes,
dtypes or NaN). The library's errors are graphslam.Error and its subclasses InputError
(also a ValueError) and RegistryError (also a LookupError), with the library's messages.
"""

from ._graphslam import (  # noqa: F401  (the public API)
    Error,
    Graph,
    IncrementalOptimizer,
    InputError,
    Marginals,
    OptimizeResult,
    RegistryError,
    Trajectory,
    __version__,
    _register_edge,
    add_wrong_loop_closures,
    certify,
    check_observability,
    configure_process,
    dead_reckon,
    dead_reckon_se2,
    edge_tags,
    drivebot,
    eval,
    graph_formats,
    initialize,
    kernels,
    load,
    load_plugins,
    marginals,
    optimize,
    parameter_tags,
    pose_graph_from_relative_poses,
    read_relative_poses,
    set_blas_threads,
    set_log_level,
    simulate_manhattan,
    simulate_pose_graph_3d,
    solvers,
    verify_certificate,
    vertex_tags,
    write_view,
)

__all__ = [
    "Error",
    "Graph",
    "IncrementalOptimizer",
    "InputError",
    "Marginals",
    "OptimizeResult",
    "RegistryError",
    "Trajectory",
    "add_wrong_loop_closures",
    "certify",
    "check_observability",
    "configure_process",
    "dead_reckon",
    "dead_reckon_se2",
    "edge_tags",
    "drivebot",
    "eval",
    "graph_formats",
    "initialize",
    "kernels",
    "load",
    "load_plugins",
    "marginals",
    "optimize",
    "parameter_tags",
    "pose_graph_from_relative_poses",
    "read_relative_poses",
    "set_blas_threads",
    "set_log_level",
    "simulate_manhattan",
    "simulate_pose_graph_3d",
    "solvers",
    "verify_certificate",
    "vertex_tags",
    "write_view",
]



class CustomEdge:
    """Base of edge types written in Python; register a subclass with register_edge.

    A subclass sets the class attributes
      tag                    the .g2o tag ("EDGE_RANGE_PY"), not yet registered
      vertex_tags            the vertex tags of its slots, e.g. ("VERTEX_SE2", "VERTEX_XY")
      dimension              the error's dimension
      measurement_dimension  the measurement's numbers (default: dimension)
    and defines error(self, estimates, measurement): `estimates` is a list of 1-D numpy
    arrays, each vertex's estimate as its .g2o line holds it (SE2: x, y, theta), and
    `measurement` a 1-D array; it returns the error (dimension,). Jacobians are central
    differences on each vertex's own update (its manifold), computed by the library.

    The edges then work like any type: Graph.add_edge(tag, ...), optimize, save and load.
    Their errors are evaluated in Python (serially, with the GIL), so they cost far more
    than the library's own types.
    """

    tag = None
    vertex_tags = ()
    dimension = None
    measurement_dimension = None

    def error(self, estimates, measurement):
        """The error (dimension,) at the vertices' `estimates` (a list of 1-D arrays, their
        .g2o data) for the `measurement` (1-D array); subclasses define it."""
        raise NotImplementedError(f"{type(self).__name__} does not define error()")


def register_edge(edge_type):
    """Registers a CustomEdge subclass (or an instance of one) under its tag; returns it."""
    instance = edge_type() if isinstance(edge_type, type) else edge_type
    if not isinstance(instance, CustomEdge):
        raise TypeError("register_edge takes a graphslam.CustomEdge subclass")
    if not instance.tag or instance.dimension is None:
        raise ValueError(f"{type(instance).__name__} must set tag and dimension")
    _register_edge(instance.tag, list(instance.vertex_tags), int(instance.dimension),
                   instance.measurement_dimension, instance.error)
    return edge_type


__all__ += ["CustomEdge", "register_edge"]

import sys as _sys

# `import graphslam.eval` and `from graphslam.eval import ape` work like a package module.
_sys.modules[__name__ + ".eval"] = eval
_sys.modules[__name__ + ".drivebot"] = drivebot
del _sys
