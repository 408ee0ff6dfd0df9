// SPDX-License-Identifier: MIT
// libFuzzer harness: every graph format of the io registry (detection, then the reader)
// reading its input through a pipe, as `cat FILE | graphslam optimize /dev/stdin` does, and
// from memory. The two must agree exactly: the same error message, or graphs of the same
// vertices and edges (a reader that looked at the head and then read the rest again would
// lose what the head took from the pipe). Bad input must come back as an InputError, never
// as a crash, a hang or another exception.
#include <unistd.h>

#include <csignal>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <thread>

#include "graphslam/core/type_registry.h"
#include "graphslam/io/graph_file.h"
#include "graphslam/io/register.h"
#include "graphslam/io/source.h"
#include "graphslam/support/error.h"
#include "graphslam/types_slam2d/register.h"
#include "graphslam/types_slam3d/register.h"

namespace {
struct Registries {
  graphslam::TypeRegistry types;
  graphslam::io::FormatRegistry formats;
  Registries() {
    graphslam::types_slam2d::registerTypes(types);
    graphslam::types_slam3d::registerTypes(types);
    graphslam::io::registerFormats(formats);
  }
};
const Registries& registries() {
  static const Registries* r = new Registries;  // lives for the process, like the tool's
  return *r;
}

/// "vertices V edges E" of the graph `source` holds, or its error message.
std::string outcome(graphslam::io::Source& source) {
  const Registries& r = registries();
  graphslam::io::ReadContext context;
  context.types = &r.types;
  context.load.max_line_bytes = 4096;
  context.load.chunk_bytes = 4096;
  try {
    const auto file = graphslam::io::readGraph(source, r.formats, context);
    return "vertices " + std::to_string(file.graph.numVertices()) + " edges " +
           std::to_string(file.graph.numEdges());
  } catch (const graphslam::InputError& e) {
    return e.what();
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A reader that stops early closes the pipe under the writer: EPIPE, not SIGPIPE.
  static const bool ignore_sigpipe = (std::signal(SIGPIPE, SIG_IGN), true);
  (void)ignore_sigpipe;
  const std::string text(reinterpret_cast<const char*>(data), size);
  int fds[2];
  if (::pipe(fds) != 0) std::abort();
  const std::string name = "/dev/fd/" + std::to_string(fds[0]);  // both sources' name
  std::thread writer([&] {  // the pipe holds 64 KiB: the reader drains it meanwhile
    std::size_t done = 0;
    while (done < text.size()) {
      const ssize_t n = ::write(fds[1], text.data() + done, text.size() - done);
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
    ::close(fds[1]);
  });
  std::string from_pipe;
  {
    auto pipe = graphslam::io::Source::open(name);
    from_pipe = outcome(pipe);
  }
  ::close(fds[0]);
  writer.join();
  auto memory = graphslam::io::Source::fromText(text, name);
  if (outcome(memory) != from_pipe) std::abort();
  return 0;
}
