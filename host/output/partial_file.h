// Kill-safe row files (docs/host.md, "Killed, interrupted and resumed runs"): the rows of a
// table go to NAME.partial as each one completes, each with one write(2), so a run killed at
// any moment leaves the header and whole rows only; when the run completes, NAME.partial is
// renamed to NAME (rename(2): a reader sees the old file or the whole new one, never a part).
// A run that does not complete leaves NAME.partial, and any older NAME, as they are.
#pragma once

#include <cstddef>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace swum::host {

/// NAME.partial: where the rows of NAME are written until the run completes.
std::filesystem::path partial_path(const std::filesystem::path& path);

class PartialFile {
 public:
  /// Starts NAME.partial afresh (an old one is truncated) with `header`.
  PartialFile(const std::filesystem::path& path, std::string_view header);
  /// Continues NAME.partial: keeps its first `keep_bytes` bytes (cuts the rest) and appends.
  static PartialFile resume(const std::filesystem::path& path, std::size_t keep_bytes);
  ~PartialFile();  // closes; the .partial stays unless commit() renamed it
  PartialFile(PartialFile&& other) noexcept;
  PartialFile(const PartialFile&) = delete;
  PartialFile& operator=(const PartialFile&) = delete;
  PartialFile& operator=(PartialFile&&) = delete;

  /// Writes `text` (whole rows) at once; throws CommandError "writing NAME.partial: <errno text>".
  void append(std::string_view text);
  /// fsync, close, rename NAME.partial to NAME; throws CommandError with the errno text.
  void commit();
  /// Closes and deletes NAME.partial (a run that wrote no row leaves nothing behind).
  void discard();

  const std::filesystem::path& path() const { return path_; }
  const std::filesystem::path& partial() const { return partial_; }

 private:
  PartialFile(const std::filesystem::path& path, int fd);
  void close_checked();

  std::filesystem::path path_;
  std::filesystem::path partial_;
  int fd_ = -1;
};

/// The whole lines of NAME.partial, each without its '\n'; a last line without one (a write
/// cut short) is left out. Throws CommandError "no NAME.partial to resume ..." when absent.
std::vector<std::string> read_partial_lines(const std::filesystem::path& path);

/// Rows that complete in any order (parallel workers), appended in index order: a row waits
/// until every row before it is written, so the file is always a prefix of the final one.
class InOrderRows {
 public:
  /// Row `first` is the next one to write (the rows before it are in the file already).
  InOrderRows(PartialFile& file, std::size_t first) : file_(file), next_(first) {}
  /// Thread-safe. Rows before `first` or given twice are a logic error (std::logic_error).
  void complete(std::size_t index, std::string row);
  /// Rows in the file (counted from 0, including those before `first`).
  std::size_t written() const;

 private:
  PartialFile& file_;
  mutable std::mutex mutex_;
  std::size_t next_;
  std::map<std::size_t, std::string> waiting_;
};

}  // namespace swum::host
