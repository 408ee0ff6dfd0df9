// SPDX-License-Identifier: MIT
#pragma once

#include "graphslam/core/graph.h"
#include "graphslam/core/linear_solver.h"
#include "graphslam/init/global_se2.h"

namespace graphslam::init {

/// Global initial guess for SE(3) pose graphs (VERTEX_SE3:QUAT and EDGE_SE3:QUAT), in two
/// linear least-squares steps (chordal relaxation, as Martinec and Pajdla; Carlone et al.,
/// "Initialization techniques for 3D SLAM", ICRA 2015):
///  1. rotations: each R_i relaxed to a free 3x3 matrix, every edge asking R_j = R_i R_ij
///     with the weight kappa = 3 / (2 tr(Omega_R^-1)) of its rotation information; the
///     three rows of the rotations are independent problems with one matrix, solved
///     together; each result is projected onto SO(3) (nearest rotation, by SVD);
///  2. translations: with the rotations known, t_j - t_i = R_i t_ij is linear; weighted by
///     tau = 3 / tr(Omega_t^-1) (the weights SE-Sync derives from the information).
/// Fixed vertices anchor the solution; a connected group without one keeps its lowest-id
/// pose where it is (so the result stays in the caller's frame). Replaces the estimates of
/// every other VertexSE3 reached by an active EDGE_SE3:QUAT; then places every non-fixed
/// VERTEX_TRACKXYZ from its first EDGE_SE3_TRACKXYZ observation (InitializationReport::
/// landmarks); other vertices and edge types are left alone. Works on graphs whose estimates are
/// all identity (edges-only files). Both systems are solved with Eigen's simplicial LDL^T (AMD
/// ordering).
InitializationReport initializeChordal3d(Graph& graph);

/// The same, solving both systems with `solver` (from a SolverRegistry; "auto" picks a
/// nested-dissection ordering and a supernodal factorisation on large graphs). A null
/// solver means the default.
InitializationReport initializeChordal3d(Graph& graph, LinearSolver* solver);

}  // namespace graphslam::init
