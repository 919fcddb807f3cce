#include "output/partial_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "commands/command_error.h"
#include "output/text_files.h"

namespace swum::host {
namespace {

std::string errno_text() { return std::strerror(errno); }

int open_or_throw(const std::filesystem::path& partial, int flags) {
  const int fd = ::open(partial.c_str(), flags | O_CLOEXEC, 0666);
  if (fd < 0) throw CommandError("cannot write " + partial.string() + ": " + errno_text());
  return fd;
}

}  // namespace

std::filesystem::path partial_path(const std::filesystem::path& path) { return path.string() + ".partial"; }

PartialFile::PartialFile(const std::filesystem::path& path, int fd)
    : path_(path), partial_(partial_path(path)), fd_(fd) {}

PartialFile::PartialFile(const std::filesystem::path& path, std::string_view header)
    : PartialFile(path, open_or_throw(partial_path(path), O_WRONLY | O_CREAT | O_TRUNC)) {
  append(header);
}

PartialFile PartialFile::resume(const std::filesystem::path& path, std::size_t keep_bytes) {
  PartialFile file(path, open_or_throw(partial_path(path), O_WRONLY | O_APPEND));
  if (::ftruncate(file.fd_, static_cast<off_t>(keep_bytes)) != 0) {
    throw CommandError("cannot write " + file.partial_.string() + ": " + errno_text());
  }
  return file;
}

PartialFile::PartialFile(PartialFile&& other) noexcept
    : path_(std::move(other.path_)), partial_(std::move(other.partial_)), fd_(std::exchange(other.fd_, -1)) {}

PartialFile::~PartialFile() {
  if (fd_ >= 0) ::close(fd_);
}

void PartialFile::append(std::string_view text) {
  if (fd_ < 0) throw std::logic_error("PartialFile::append after commit or discard");
  // One write(2) for the whole text: a SIGKILL lands before or after it, never inside a row.
  // The loop only continues a short write (disk nearly full) or a call cut short by a signal.
  while (!text.empty()) {
    const ssize_t n = ::write(fd_, text.data(), text.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw CommandError("writing " + partial_.string() + ": " + errno_text());
    text.remove_prefix(static_cast<std::size_t>(n));
  }
}

void PartialFile::close_checked() {
  const int fd = std::exchange(fd_, -1);
  if (::close(fd) != 0) throw CommandError("writing " + partial_.string() + ": " + errno_text());
}

void PartialFile::commit() {
  // On disk before the rename: after a power cut NAME is the whole file or the old one.
  if (::fsync(fd_) != 0) throw CommandError("writing " + partial_.string() + ": " + errno_text());
  close_checked();
  if (std::rename(partial_.c_str(), path_.c_str()) != 0) {
    throw CommandError("cannot rename " + partial_.string() + " to " + path_.string() + ": " + errno_text());
  }
}

void PartialFile::discard() {
  close_checked();
  std::remove(partial_.c_str());
}

std::vector<std::string> read_partial_lines(const std::filesystem::path& path) {
  const std::filesystem::path partial = partial_path(path);
  std::error_code ec;
  if (!std::filesystem::exists(partial, ec)) {
    throw CommandError("--resume: there is no " + partial.string() + " to continue (run without --resume)");
  }
  const std::string text = read_text_file(partial);
  std::vector<std::string> lines;
  std::size_t start = 0;
  for (std::size_t end = text.find('\n'); end != std::string::npos; end = text.find('\n', start)) {
    lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

void InOrderRows::complete(std::size_t index, std::string row) {
  const std::lock_guard lock(mutex_);
  if (index < next_ || !waiting_.emplace(index, std::move(row)).second) {
    throw std::logic_error("InOrderRows: row " + std::to_string(index) + " completed twice");
  }
  // Everything now contiguous goes out in one write.
  std::string text;
  for (auto it = waiting_.begin(); it != waiting_.end() && it->first == next_; it = waiting_.erase(it), ++next_) {
    text += it->second;
  }
  if (!text.empty()) file_.append(text);
}

std::size_t InOrderRows::written() const {
  const std::lock_guard lock(mutex_);
  return next_;
}

}  // namespace swum::host
