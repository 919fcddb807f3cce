#include "output/progress_bar.h"

#include <unistd.h>

#include <cstdio>

namespace swum::host {

ProgressBar::ProgressBar(std::string label, std::size_t total)
    : label_(std::move(label)), total_(total), enabled_(isatty(STDERR_FILENO) == 1 && total > 0) {
  if (enabled_) draw(0);
}

ProgressBar::~ProgressBar() {
  if (enabled_) std::fputc('\n', stderr);
}

void ProgressBar::advance() {
  const std::size_t done = ++done_;
  if (enabled_) draw(done);
}

void ProgressBar::draw(std::size_t done) {
  const std::lock_guard lock(draw_mutex_);
  constexpr int kWidth = 40;
  const int filled = static_cast<int>(kWidth * done / total_);
  std::fprintf(stderr, "\r%s [", label_.c_str());
  for (int i = 0; i < kWidth; ++i) std::fputc(i < filled ? '#' : '.', stderr);
  std::fprintf(stderr, "] %zu/%zu", done, total_);
  std::fflush(stderr);
}

}  // namespace swum::host
