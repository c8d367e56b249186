// Files an attacker or an unlucky user hands to a reader: FIFOs, and a way to
// read them that fails the test instead of hanging when a reader blocks.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace facerig::test {

// Creates a FIFO (named pipe) at `path`, replacing whatever was there.
void MakeFifo(const std::filesystem::path& path);

// Runs `read` on another thread and returns what() of the IoError it throws
// ("no error" when it returns). If it is still running after a few seconds,
// the test fails and the FIFO `fifo` is opened for writing and closed, which
// releases a reader blocked on it.
std::string ErrorWithoutHanging(const std::filesystem::path& fifo, const std::function<void()>& read);

}  // namespace facerig::test
