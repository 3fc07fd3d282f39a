// What every fuzz target holds a parser to, and the scratch file it feeds it through.
//
// A parser given any bytes either returns, or throws a std::runtime_error (or a type
// derived from it) whose message is one line that begins with the file's name: the
// tools print that line and exit non-zero. Anything else is a finding: another
// exception type (a raw library or std::logic_error escaping), a message that does not
// name the file or spans lines, a crash, a sanitizer report, a hang (libFuzzer's
// -timeout) or an allocation above its -malloc_limit_mb.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>

namespace fov::fuzz {

// Writes the input to `name` in a directory of this process under $TMPDIR (or /tmp),
// replacing what the previous input left there, and returns its path.
std::string write_input(const uint8_t* data, size_t size, const std::string& name);
// The directory write_input writes to (created on first use, removed at exit).
const std::string& scratch_dir();

[[noreturn]] inline void finding(const char* what, const char* detail) {
  std::fprintf(stderr, "fuzz finding: %s: %s\n", what, detail);
  std::abort();
}

// Holds an error message to the rule above.
inline void check_message(const std::string& file, const std::string& message) {
  if (message.rfind(file, 0) != 0) finding("the message does not begin with the file's name", message.c_str());
  if (message.find('\n') != std::string::npos) finding("the message spans lines", message.c_str());
}

// Runs `parse`; an error must be a one-line std::runtime_error naming `file`. With
// FOV_FUZZ_VERBOSE set, says whether each input was accepted or refused, and why.
template <class F>
void expect_clean(const std::string& file, F&& parse) {
  try {
    parse();
  } catch (const std::runtime_error& e) {
    check_message(file, e.what());
    if (std::getenv("FOV_FUZZ_VERBOSE")) std::fprintf(stderr, "  refused: %s\n", e.what());
    return;
  } catch (const std::exception& e) {
    finding("an exception that is not a std::runtime_error escaped", e.what());
  }
  if (std::getenv("FOV_FUZZ_VERBOSE")) std::fprintf(stderr, "  accepted\n");
}

// Holds a parsed result to a property: a finding when it is false.
inline void require(bool property, const char* what) {
  if (!property) finding("accepted input breaks an invariant", what);
}

}  // namespace fov::fuzz
