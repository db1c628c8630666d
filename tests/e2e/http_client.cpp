#include "http_client.h"

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "process.h"

namespace mesh4d::testing {

Http curl(const std::string& dir, const std::string& url, std::vector<std::string> args,
          int seconds) {
  static std::atomic<int> calls = 0;  // tests call from several threads
  const int call = ++calls;
  const std::string headers = dir + "/headers" + std::to_string(call);
  const std::string body = dir + "/body" + std::to_string(call);
  std::vector<std::string> argv{"/usr/bin/curl", "-sS", "-N", "-D", headers, "-o", body, url};
  argv.insert(argv.end(), args.begin(), args.end());
  const RunResult r = run_command(argv, std::chrono::seconds(seconds));
  Http h;
  std::ifstream hin(headers), bin(body, std::ios::binary);
  std::stringstream hs, bs;
  hs << hin.rdbuf();
  bs << bin.rdbuf();
  h.headers = hs.str();
  h.body = bs.str();
  // Long runs (the soak test) make thousands of calls: nothing is kept on disk.
  std::filesystem::remove(headers);
  std::filesystem::remove(body);
  if (r.exit_code == 0 && h.headers.rfind("HTTP/1.1 ", 0) == 0)
    h.status = std::stoi(h.headers.substr(9, 3));
  return h;
}

std::string header(const Http& h, const std::string& name) {
  std::istringstream in(h.headers);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(name + ": ", 0) == 0) {
      std::string value = line.substr(name.size() + 2);
      if (!value.empty() && value.back() == '\r') value.pop_back();
      return value;
    }
  return "";
}

}  // namespace mesh4d::testing
