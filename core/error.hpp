#pragma once
// The one exception type of qmaps: a message for the user and the process exit code it maps to.
#include <charconv>
#include <stdexcept>
#include <string>

namespace qmaps {

enum class ExitCode : int {
  ok = 0,
  failure = 1,       // an error inside qmaps or its libraries
  usage = 2,         // bad command line, configuration or parameters
  io = 3,            // a file that cannot be read or written
  unsupported = 4,   // an ISA that this binary or this CPU lacks
  interrupted = 5,   // SIGINT or SIGTERM: a checkpoint was written; `qmaps run --resume` goes on
};

class Error : public std::runtime_error {
 public:
  Error(ExitCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ExitCode code() const { return code_; }

 private:
  ExitCode code_;
};

inline Error usage_error(const std::string& message) { return Error(ExitCode::usage, message); }

// The shortest text that reads back as exactly x (for messages: -1e-09, not -0.000000).
inline std::string number_text(double x) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, x).ptr;
  return std::string(text, end);
}

}  // namespace qmaps
