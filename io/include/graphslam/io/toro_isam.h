// SPDX-License-Identifier: MIT
// The other common pose-graph text formats, read by translation into .g2o text:
//
//   TORO  VERTEX2 id x y theta                       -> VERTEX_SE2
//         EDGE2 i j x y theta  I_xx I_xy I_yy I_tt I_xt I_yt
//                                                    -> EDGE_SE2 (information reordered to
//                                                       g2o's xx xy xt yy yt tt)
//         VERTEX3 id x y z roll pitch yaw            -> VERTEX_SE3:QUAT
//         EDGE3 i j x y z roll pitch yaw  I (21, upper triangle, in x y z roll pitch yaw)
//                                                    -> EDGE_SE3:QUAT (information mapped
//                                                       to the quaternion error, as g2o's
//                                                       EDGE3 reader does: toroInformation3d)
//         (VERTEX and EDGE: TORO's older names of VERTEX2 and EDGE2)
//   iSAM  EDGE2|ODOMETRY|Constraint2 i j x y theta  R_11 R_12 R_13 R_22 R_23 R_33
//                                                    -> EDGE_SE2, information R^T R (iSAM
//                                                       stores the square root information)
//         LANDMARK i l x y  R_11 R_12 R_22           -> EDGE_SE2_XY i (l + offset), R^T R
//         iSAM files hold no vertices: the reader creates them from the edges
//         (io::LoadOptions::create_missing_vertices). Landmark ids live in their own
//         namespace in iSAM: when they collide with pose ids, landmark l becomes vertex
//         max_pose_id + 1 + l (Translation::landmark_id_offset), else it keeps its id.
//
// One output line per input line (`#` comments and blank lines stay blank), so the .g2o
// reader's FILE:LINE diagnostics point into the source file. Vertex ids are copied as they
// are and checked by the .g2o reader.
//
//   auto text = io::readText(path);                  // throws graphslam::Error
//   auto format = io::detectTextFormat(text);
//   io::Translation t = io::translate(text, path, format);
//   if (!t.ok()) ...  t.diagnostics
//   std::istringstream in(t.g2o);  io::readG2o(in, path, types, options);
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <string_view>
#include <vector>

#include "graphslam/core/vertex.h"
#include "graphslam/io/g2o.h"

namespace graphslam::io {

enum class TextFormat { kG2o, kToro, kIsam };

/// "g2o", "toro", "isam" (the tool's option values).
[[nodiscard]] const char* toString(TextFormat format);
/// ".g2o", "TORO", "iSAM" (for messages).
[[nodiscard]] const char* displayName(TextFormat format);

/// The format of `text` from its tags: the first non-comment line's tag is TORO's or
/// iSAM's (VERTEX2, EDGE2, VERTEX3, EDGE3, VERTEX, EDGE, ODOMETRY, LANDMARK, Constraint2),
/// else kG2o. EDGE2 and EDGE3 are both formats' tags: a file with any VERTEX2/VERTEX3/
/// VERTEX line is TORO, one without is iSAM (iSAM files hold no vertices).
[[nodiscard]] TextFormat detectTextFormat(std::string_view text);

/// detectTextFormat on the file at `path`, reading only its start unless its first tag is
/// EDGE2 or EDGE3 (then the whole file). Throws graphslam::Error when it cannot be read.
[[nodiscard]] TextFormat detectFileFormat(const std::string& path);

/// A TORO or iSAM file as .g2o text.
struct Translation {
  std::string g2o;                          ///< the translated text, line for line
  std::vector<io::Diagnostic> diagnostics;  ///< bad lines (FILE:LINE: reason); empty if ok
  std::size_t vertices = 0;                 ///< vertex lines
  std::size_t edges = 0;                    ///< edge lines
  /// iSAM: landmark l became vertex l + landmark_id_offset (0: the ids did not collide).
  VertexId landmark_id_offset = 0;
  [[nodiscard]] bool ok() const { return diagnostics.empty(); }
};

/// Translates TORO text (`name` is used in diagnostics). Every bad line is reported.
[[nodiscard]] Translation translateToro(std::string_view text, const std::string& name);
/// Translates iSAM text. iSAM's 3D lines (EDGE3 with square-root information) are refused
/// with a message saying so.
[[nodiscard]] Translation translateIsam(std::string_view text, const std::string& name);
/// translateToro or translateIsam; kG2o returns the text unchanged.
[[nodiscard]] Translation translate(std::string_view text, const std::string& name,
                                    TextFormat format);

/// The whole file (throws graphslam::Error naming the file and the system's reason).
[[nodiscard]] std::string readText(const std::string& path);

/// The rotation R = Rz(yaw) Ry(pitch) Rx(roll) (TORO's and g2o's Euler convention).
[[nodiscard]] Eigen::Quaterniond quaternionFromRollPitchYaw(double roll, double pitch, double yaw);

/// d(x y z roll pitch yaw) / d(x y z qx qy qz) at the pose (t, q): how the Euler
/// parameters move with g2o's compact quaternion (vector part of q with q_w >= 0).
/// Singular where pitch is +-90 degrees.
[[nodiscard]] Eigen::Matrix<double, 6, 6> eulerFromCompactQuaternionJacobian(
    const Eigen::Quaterniond& q);

/// TORO's 3D information (on x y z roll pitch yaw) as the information of g2o's
/// EDGE_SE3:QUAT error: J^T I J with J = eulerFromCompactQuaternionJacobian(measurement),
/// which is what g2o's own EDGE3 reader computes (by numeric differences).
[[nodiscard]] Eigen::Matrix<double, 6, 6> toroInformation3d(
    const Eigen::Quaterniond& measurement, const Eigen::Matrix<double, 6, 6>& information);

}  // namespace graphslam::io
