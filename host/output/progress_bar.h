// A progress bar on stderr, shown only when stderr is a terminal (so logs and
// pipes stay clean). Thread-safe: workers call advance() as points finish.
#pragma once

#include <atomic>
#include <cstddef>
#include <mutex>
#include <string>

namespace swum::host {

class ProgressBar {
 public:
  ProgressBar(std::string label, std::size_t total);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void advance();

 private:
  void draw(std::size_t done);

  std::string label_;
  std::size_t total_;
  std::atomic<std::size_t> done_{0};
  bool enabled_;
  std::mutex draw_mutex_;
};

}  // namespace swum::host
