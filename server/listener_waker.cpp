#include "listener_waker.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>

namespace mesh4d::server {

ListenerWaker::ListenerWaker(std::vector<int> ports)
    : thread_([this, ports = std::move(ports)] {
        while (!done_) {
          for (int port : ports) {
            if (port == 0) continue;
            const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
            if (fd < 0) continue;
            sockaddr_in a{};
            a.sin_family = AF_INET;
            a.sin_port = htons(static_cast<std::uint16_t>(port));
            a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
            // Refused once the server is gone: that is fine, the point is the wake-up.
            ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
            ::close(fd);
          }
          std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
      }) {}

ListenerWaker::~ListenerWaker() {
  done_ = true;
  thread_.join();
}

}  // namespace mesh4d::server
