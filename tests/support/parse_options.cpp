#include "support/parse_options.h"

#include "options.h"

namespace clpt::test {

ExitCode parse_error(std::vector<const char*> args) {
  args.insert(args.begin(), "clpt");
  try {
    (void)parse_options(int(args.size()), args.data());
  } catch (const Error& e) {
    return e.code();
  }
  return ExitCode::Ok;
}

}  // namespace clpt::test
