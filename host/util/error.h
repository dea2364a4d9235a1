// One error type for the whole program: a message for the user and the exit code
// the process ends with. Thrown wherever the problem is found, caught once in main().
#pragma once

#include <stdexcept>
#include <string>

namespace clpt {

enum class ExitCode : int {
  Ok = 0,
  Usage = 1,        // bad command line
  BadInput = 2,     // scene or other input file is malformed or unsupported
  Device = 3,       // no device, kernel build failure, device out of memory
  Output = 4,       // the output image could not be written
  Interrupted = 130 // stopped by SIGINT/SIGTERM (what was rendered is saved)
};

class Error : public std::runtime_error {
 public:
  Error(ExitCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ExitCode code() const { return code_; }

 private:
  ExitCode code_;
};

}  // namespace clpt
