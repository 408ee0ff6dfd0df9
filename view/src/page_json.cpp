// SPDX-License-Identifier: MIT
// The page's data as JSON: small fields as text, the arrays as base64 of little-endian typed
// arrays (Float32Array, Int32Array, Uint32Array, Uint8Array in the page), so that the page
// grows by a few bytes per vertex and edge.
#include <cmath>
#include <cstdio>
#include <string>

#include "scene_data.h"

namespace graphslam::view {

std::string base64(const void* data, std::size_t bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((bytes + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes; i += 3) {
    const unsigned v = (unsigned{p[i]} << 16) | (unsigned{p[i + 1]} << 8) | p[i + 2];
    out += table[v >> 18];
    out += table[(v >> 12) & 63];
    out += table[(v >> 6) & 63];
    out += table[v & 63];
  }
  if (i < bytes) {
    const unsigned v = (unsigned{p[i]} << 16) | (i + 1 < bytes ? unsigned{p[i + 1]} << 8 : 0u);
    out += table[v >> 18];
    out += table[(v >> 12) & 63];
    out += i + 1 < bytes ? table[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string jsonString(const std::string& text) {
  std::string out = "\"";
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20 || c == '<' || c == '>' || c == '&' || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

namespace {

/// Base64 needs no escaping in JSON or HTML.
template <typename T>
std::string array(const std::vector<T>& v) {
  return "\"" + base64(v.data(), v.size() * sizeof(T)) + "\"";
}

std::string strings(const std::vector<std::string>& v) {
  std::string out = "[";
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? "," : "") + jsonString(v[i]);
  return out + "]";
}

std::string number(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

std::string framesJson(const Scene::Data& d) {
  std::string out = "[";
  for (std::size_t f = 0; f < d.frame_pos.size(); ++f) {
    out += (f ? ",{" : "{");
    out += "\"label\":" + jsonString(d.frame_labels[f]);
    out += ",\"objective\":" + number(d.frame_objective[f]);
    out += ",\"pos\":" + array(d.frame_pos[f]);
    out += ",\"chi2\":" + array(d.frame_chi2[f]) + "}";
  }
  return out + "]";
}

}  // namespace

std::string dataJson(const Scene::Data& d, const std::string& title, const std::string& source,
                     const Options& options, const std::string& extra) {
  std::string kinds;
  for (std::size_t i = 0; i < d.tag_kinds.size(); ++i) {
    kinds += (i ? "," : "") + std::to_string(static_cast<int>(d.tag_kinds[i]));
  }
  std::string out = "{\"format\":1,\"dim\":" + std::to_string(d.dim);
  out += ",\"title\":" + jsonString(title) + ",\"source\":" + jsonString(source);
  out += ",\"lodEdges\":" + std::to_string(options.lod_edges);
  out += ",\"vertexTags\":" + strings(d.vertex_tags) + ",\"vertexTagKinds\":[" + kinds + "]";
  out += ",\"edgeTags\":" + strings(d.edge_tags) + ",\"notes\":" + strings(d.notes);
  out +=
      ",\"vid\":" + array(d.vid) + ",\"vtag\":" + array(d.vtag) + ",\"vfixed\":" + array(d.vfixed);
  out += ",\"vline\":" + array(d.vline);
  out += ",\"ea\":" + array(d.ea) + ",\"eb\":" + array(d.eb) + ",\"ekind\":" + array(d.ekind);
  out += ",\"etag\":" + array(d.etag) + ",\"eflag\":" + array(d.eflag);
  out += ",\"eweight\":" + array(d.eweight) + ",\"eline\":" + array(d.eline);
  out += ",\"xedge\":" + array(d.xedge) + ",\"xvertex\":" + array(d.xvertex);
  if (!d.edim.empty()) out += ",\"edim\":" + array(d.edim) + ",\"eerr\":" + array(d.eerr);
  out += ",\"hasInitial\":" + std::string(d.has_initial ? "true" : "false");
  out += ",\"frames\":" + framesJson(d);
  if (!d.truth_pos.empty()) {
    out += ",\"truth\":" + array(d.truth_pos) + ",\"ape\":" + array(d.ape);
  }
  return out + extra + "}";
}

}  // namespace graphslam::view
