#include "support/hostile_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <future>

#include <catch2/catch.hpp>

#include "facerig/runtime/error.h"

namespace facerig::test {

void MakeFifo(const std::filesystem::path& path) {
  std::filesystem::remove(path);
  REQUIRE(::mkfifo(path.c_str(), 0600) == 0);
}

std::string ErrorWithoutHanging(const std::filesystem::path& fifo, const std::function<void()>& read) {
  std::future<std::string> result = std::async(std::launch::async, [&read] {
    try {
      read();
    } catch (const IoError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  });
  if (result.wait_for(std::chrono::seconds(5)) != std::future_status::ready) {
    FAIL_CHECK("reading blocked on the FIFO " << fifo);
    const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
    if (fd >= 0) ::close(fd);
  }
  return result.get();
}

}  // namespace facerig::test
