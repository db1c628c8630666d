// civetweb's listening thread notices that its server is stopping only when its poll of the
// listening sockets returns, which it does once a second or so when no client connects: a
// stop of the REST and metrics faces took 1 s each, 3 s for both. While a ListenerWaker lives it
// connects to the given loopback ports every few milliseconds, so that a civetweb server closed
// meanwhile stops at once.
#pragma once

#include <atomic>
#include <thread>
#include <vector>

namespace mesh4d::server {

class ListenerWaker {
 public:
  explicit ListenerWaker(std::vector<int> ports);  // 0s are skipped
  ~ListenerWaker();
  ListenerWaker(const ListenerWaker&) = delete;
  ListenerWaker& operator=(const ListenerWaker&) = delete;

 private:
  std::atomic<bool> done_{false};
  std::thread thread_;
};

}  // namespace mesh4d::server
