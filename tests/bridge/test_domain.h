// DDS domain ids for tests that run at the same time in several processes (ctest -j): each
// id is claimed with an exclusive lock on /tmp/plumb-dds-domain-<id>.lock, held until the
// process ends, so no two running tests share a domain (and so their topics).

#ifndef PLUMB_TESTS_BRIDGE_TEST_DOMAIN_H_
#define PLUMB_TESTS_BRIDGE_TEST_DOMAIN_H_

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdint>
#include <stdexcept>
#include <string>

namespace plumb::testing {

// A domain id (10..229) nobody else on this machine is using for a test right now.
inline std::uint32_t FreeDomain() {
  static std::uint32_t next = 10;
  for (; next < 230; ++next) {
    std::string lock = "/tmp/plumb-dds-domain-" + std::to_string(next) + ".lock";
    int fd = open(lock.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0666);
    if (fd < 0) continue;
    if (flock(fd, LOCK_EX | LOCK_NB) == 0) return next++;  // kept open: held to the end
    close(fd);
  }
  throw std::runtime_error("no free DDS domain id between 10 and 229 for this test");
}

}  // namespace plumb::testing

#endif  // PLUMB_TESTS_BRIDGE_TEST_DOMAIN_H_
