// napkin_serve_bench: the measurements of bench/run_serve.sh against a running
// `napkin serve` (docs/serve.md), over loopback only.
//
//   napkin_serve_bench write-tests DIR COUNT SAMPLES FIRST_SEED
//     Writes COUNT raw recordings DIR/bench-<seed>.csv (denton-3222, 9
//     channels x SAMPLES samples at 10 kHz, random smooth motions): what a data
//     acquisition system would drop into the inbox.
//
//   napkin_serve_bench latency PORT STAGING TARGET_DIR SAMPLES REPEATS SETTLE_S FIRST_SEED [marker]
//     REPEATS times: writes one such recording into STAGING (same file system
//     as TARGET_DIR), renames it into TARGET_DIR (from then on it is settled:
//     its size and time never change again) and asks GET /api/v1/tests/ID
//     every 2 ms until the test has a HIC row. With `marker`, a `<id>.ready`
//     marker is written right after the rename and SETTLE_S is not waited
//     for. Prints each latency beyond SETTLE_S and their median.
//
//   napkin_serve_bench load PORT PATH CLIENTS REQUESTS MAX_SECONDS
//     CLIENTS keep-alive connections, each on its own thread, send GET PATH
//     until REQUESTS requests are answered in all or MAX_SECONDS pass.
//     Prints the count, the answers that were not 200, requests per second
//     and the 50th and 99th percentile latency.
//
//   napkin_serve_bench wait PORT PROCESSED MAX_SECONDS
//     Waits until the inbox has processed or failed PROCESSED tests in all
//     (GET /api/v1/status), asking every 50 ms; prints the seconds waited.
//
//   napkin_serve_bench processed PORT
//     The tests the inbox has processed so far.
//
//   napkin_serve_bench rss PID
//     The resident memory (VmRSS, kB) of process PID.
#include <fmt/core.h>
#include <httplib.h>
// httplib.h includes glibc's <resolv.h>, whose macro _res (the resolver's state) is a parameter
// name in Eigen's headers (as in serve/service.cpp).
#ifdef _res
#undef _res
#endif
#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "formats/array_json.h"
#include "formats/csv.h"
#include "synth/synthetic_tests.h"

namespace {

using namespace napkin;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double Percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const auto at = static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1) + 0.5);
  return values[std::min(at, values.size() - 1)];
}

// A recording of `samples` samples per channel (10 kHz), as the DAQ writes it.
void WriteRecording(const fs::path& path, int samples, std::uint64_t seed) {
  synth::RandomMotionOptions options;
  options.seed = seed;
  options.duration_s = (samples - 1) / options.synth.rate_hz;
  formats::WriteSignalsCsv(synth::SynthRandomMotion(formats::LoadArray("denton-3222"), options).signals,
                           path);
}

int WriteTests(const fs::path& dir, int count, int samples, std::uint64_t first_seed) {
  fs::create_directories(dir);
  for (int i = 0; i < count; ++i)
    WriteRecording(dir / fmt::format("bench-{}.csv", first_seed + i), samples, first_seed + i);
  return 0;
}

httplib::Client LoopbackClient(int port) {
  httplib::Client client("127.0.0.1", port);
  client.set_keep_alive(true);
  client.set_tcp_nodelay(true);  // as browsers do
  client.set_connection_timeout(5, 0);
  client.set_read_timeout(30, 0);
  return client;
}

int Latency(int port, const fs::path& staging, const fs::path& target_dir, int samples, int repeats,
            double settle_s, std::uint64_t first_seed, bool marker) {
  httplib::Client client = LoopbackClient(port);
  fs::create_directories(staging);
  fs::create_directories(target_dir);
  std::vector<double> beyond_settle_s;
  for (int i = 0; i < repeats; ++i) {
    const std::string id = fmt::format("bench-{}", first_seed + i);
    WriteRecording(staging / (id + ".csv"), samples, first_seed + i);
    const Clock::time_point settled_at = Clock::now();
    // Into the inbox in one step, never over a file already there.
    const fs::path staged = staging / (id + ".csv"), target = target_dir / (id + ".csv");
    if (::renameat2(AT_FDCWD, staged.c_str(), AT_FDCWD, target.c_str(), RENAME_NOREPLACE) != 0)
      throw std::runtime_error("cannot move " + staged.string() + " to " + target.string() + ": " +
                               std::strerror(errno));
    if (marker) std::ofstream(target_dir / (id + ".ready")).flush();
    for (;;) {
      const httplib::Result answer = client.Get("/api/v1/tests/" + id);
      if (answer && answer->status == 200 && !nlohmann::json::parse(answer->body).at("hic").is_null()) break;
      if (SecondsSince(settled_at) > settle_s + 120) {
        fmt::print(stderr, "{}: no HIC row 120 s after it settled\n", id);
        return 1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    beyond_settle_s.push_back(SecondsSince(settled_at) - (marker ? 0.0 : settle_s));
    fmt::print("{}: {:.3f} s\n", id, beyond_settle_s.back());
  }
  fmt::print("median {:.3f} s, min {:.3f} s, max {:.3f} s beyond the settle time ({} tests, {})\n",
             Percentile(beyond_settle_s, 0.5),
             *std::min_element(beyond_settle_s.begin(), beyond_settle_s.end()),
             *std::max_element(beyond_settle_s.begin(), beyond_settle_s.end()), repeats,
             marker ? "marker files" : fmt::format("settle {} s", settle_s));
  return 0;
}

int Load(int port, const std::string& path, int clients, int requests, double max_seconds) {
  std::atomic<int> issued{0};
  std::atomic<int> not_ok{0};
  std::vector<std::vector<double>> latencies_ms(clients);
  const Clock::time_point start = Clock::now();
  {
    std::vector<std::jthread> threads;
    for (int c = 0; c < clients; ++c)
      threads.emplace_back([&, c] {
        httplib::Client client = LoopbackClient(port);
        while (issued.fetch_add(1) < requests && SecondsSince(start) < max_seconds) {
          const Clock::time_point sent = Clock::now();
          const httplib::Result answer = client.Get(path);
          latencies_ms[c].push_back(SecondsSince(sent) * 1e3);
          if (!answer || answer->status != 200) ++not_ok;
        }
      });
  }
  const double seconds = SecondsSince(start);
  std::vector<double> all_ms;
  for (const auto& some : latencies_ms) all_ms.insert(all_ms.end(), some.begin(), some.end());
  fmt::print(
      "{} requests ({} not 200) in {:.2f} s with {} clients: {:.0f} requests/s, p50 {:.2f} ms, p99 {:.2f} "
      "ms\n",
      all_ms.size(), not_ok.load(), seconds, clients, static_cast<double>(all_ms.size()) / seconds,
      Percentile(all_ms, 0.50), Percentile(all_ms, 0.99));
  return not_ok.load() == 0 ? 0 : 1;
}

int Wait(int port, int processed, double max_seconds) {
  httplib::Client client = LoopbackClient(port);
  const Clock::time_point start = Clock::now();
  for (;;) {
    const httplib::Result answer = client.Get("/api/v1/status");
    if (answer && answer->status == 200) {
      const nlohmann::json inbox = nlohmann::json::parse(answer->body).at("inbox");
      if (inbox.at("processed").get<int>() + inbox.at("failed").get<int>() >= processed) break;
    }
    if (SecondsSince(start) > max_seconds) {
      fmt::print(stderr, "the inbox did not process {} tests within {} s\n", processed, max_seconds);
      return 1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  fmt::print("{:.2f}\n", SecondsSince(start));
  return 0;
}

int Processed(int port) {
  httplib::Client client = LoopbackClient(port);
  const httplib::Result answer = client.Get("/api/v1/status");
  if (!answer || answer->status != 200) {
    fmt::print(stderr, "GET /api/v1/status failed\n");
    return 1;
  }
  fmt::print("{}\n", nlohmann::json::parse(answer->body).at("inbox").at("processed").get<int>());
  return 0;
}

int ResidentKb(const std::string& pid) {
  std::ifstream status("/proc/" + pid + "/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmRSS:", 0) == 0) {
      fmt::print("{}\n", std::stol(line.substr(6)));
      return 0;
    }
  fmt::print(stderr, "no VmRSS for process {}\n", pid);
  return 1;
}

int Usage() {
  fmt::print(stderr,
             "usage: napkin_serve_bench write-tests DIR COUNT SAMPLES FIRST_SEED\n"
             "       napkin_serve_bench latency PORT STAGING TARGET_DIR SAMPLES REPEATS SETTLE_S FIRST_SEED "
             "[marker]\n"
             "       napkin_serve_bench load PORT PATH CLIENTS REQUESTS MAX_SECONDS\n"
             "       napkin_serve_bench wait PORT PROCESSED MAX_SECONDS\n"
             "       napkin_serve_bench processed PORT\n"
             "       napkin_serve_bench rss PID\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.size() == 5 && args[0] == "write-tests")
      return WriteTests(args[1], std::stoi(args[2]), std::stoi(args[3]), std::stoull(args[4]));
    if ((args.size() == 8 || (args.size() == 9 && args[8] == "marker")) && args[0] == "latency")
      return Latency(std::stoi(args[1]), args[2], args[3], std::stoi(args[4]), std::stoi(args[5]),
                     std::stod(args[6]), std::stoull(args[7]), args.size() == 9);
    if (args.size() == 6 && args[0] == "load")
      return Load(std::stoi(args[1]), args[2], std::stoi(args[3]), std::stoi(args[4]), std::stod(args[5]));
    if (args.size() == 4 && args[0] == "wait")
      return Wait(std::stoi(args[1]), std::stoi(args[2]), std::stod(args[3]));
    if (args.size() == 2 && args[0] == "processed") return Processed(std::stoi(args[1]));
    if (args.size() == 2 && args[0] == "rss") return ResidentKb(args[1]);
  } catch (const std::exception& error) {
    fmt::print(stderr, "napkin_serve_bench: {}\n", error.what());
    return 1;
  }
  return Usage();
}
