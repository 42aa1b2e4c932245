// The one exception type of wavevcm: a message meant for the user, already
// naming the file or device concerned. Caught in main(), printed to stderr.
#pragma once

#include <stdexcept>
#include <string>

namespace wv {

class Error : public std::runtime_error {
public:
    // exitCode lets main() distinguish e.g. "no OpenCL device" (2) from other failures (1).
    explicit Error(const std::string& message, int exitCode = 1)
        : std::runtime_error(message), exitCode_(exitCode) {}
    int exitCode() const { return exitCode_; }

private:
    int exitCode_;
};

} // namespace wv
