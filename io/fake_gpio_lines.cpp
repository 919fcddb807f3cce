#include "fake_gpio_lines.h"

#include <cerrno>

namespace swum::io {

struct FakeGpioLines::State {
  struct Line {
    std::string consumer;  // empty: free
    bool output = false;
    bool output_value = false;
    std::optional<bool> driven;
    bool chip_pull_up = false;
    std::optional<bool> bias_pull_up;  // from the request
    GpioEdge edge = GpioEdge::none;
    std::deque<GpioEvent> events;
    bool failing = false;  // fault injection (fail_operations)
  };
  struct Chip {
    std::string label;
    std::vector<Line> lines;
  };
  std::mutex mutex;
  std::condition_variable changed;
  std::map<std::string, Chip> chips;

  static bool level_of(const Line& l) {
    if (l.output) return l.output_value;
    if (l.driven) return *l.driven;
    if (l.bias_pull_up) return *l.bias_pull_up;
    return l.chip_pull_up;
  }
  // Finds a line without allocating (the per-event calls look their line up each time).
  Line& line(const std::string& chip, unsigned offset) {
    auto it = chips.find(chip);
    if (it == chips.end()) throw GpioError("no such GPIO chip '" + chip + "'", ENODEV);
    if (offset >= it->second.lines.size()) {
      throw GpioError("GPIO chip '" + chip + "' line " + std::to_string(offset) + ": offset out of range, chip " +
                          chip + " [" + it->second.label + "] has " + std::to_string(it->second.lines.size()) +
                          " lines",
                      EINVAL);
    }
    return it->second.lines[offset];
  }
  // Call with the mutex held, around any change of what the line sees.
  void record_edge(Line& l, bool before) {
    const bool after = level_of(l);
    if (after == before || l.consumer.empty() || l.output) return;
    const bool wanted = l.edge == GpioEdge::both || (after && l.edge == GpioEdge::rising) ||
                        (!after && l.edge == GpioEdge::falling);
    if (!wanted) return;
    l.events.push_back(GpioEvent{after, std::chrono::steady_clock::now().time_since_epoch()});
    changed.notify_all();
  }
};

namespace {
using State = FakeGpioLines::State;

class FakeLineBase {
 public:
  FakeLineBase(std::shared_ptr<State> s, GpioLineConfig c) : state_(std::move(s)), config_(std::move(c)) {}
  ~FakeLineBase() {
    std::lock_guard lock(state_->mutex);
    auto& l = state_->line(config_.chip, config_.offset);
    l.consumer.clear();
    l.output = false;
    l.bias_pull_up.reset();
    l.edge = GpioEdge::none;
    l.events.clear();
  }

 protected:
  // The line, for an operation; null (and `failure` filled) as the real adapter fails while a
  // failure is injected. `operation` is a string literal: a failure allocates nothing, as the
  // real adapter's.
  State::Line* operable_line(const char* operation, GpioResult& failure) const {
    auto& l = state_->line(config_.chip, config_.offset);
    if (!l.failing) return &l;
    failure = gpio_failure(operation, EIO);
    return nullptr;
  }
  std::shared_ptr<State> state_;
  GpioLineConfig config_;
};

class FakeOutput final : public GpioOutputLine, FakeLineBase {
 public:
  using FakeLineBase::FakeLineBase;
  GpioResult set(bool value) override {
    std::lock_guard lock(state_->mutex);
    GpioResult r;
    if (auto* l = operable_line("set", r)) l->output_value = value;
    return r;
  }
  GpioResult get(bool& value) const override {
    std::lock_guard lock(state_->mutex);
    GpioResult r;
    if (const auto* l = operable_line("get", r)) value = l->output_value;
    return r;
  }
};

class FakeInput final : public GpioInputLine, FakeLineBase {
 public:
  using FakeLineBase::FakeLineBase;
  GpioResult get(bool& value) const override {
    std::lock_guard lock(state_->mutex);
    GpioResult r;
    if (const auto* l = operable_line("get", r)) value = State::level_of(*l);
    return r;
  }
  GpioResult wait_edge(GpioEvent& event, std::chrono::milliseconds timeout) override {
    std::unique_lock lock(state_->mutex);
    GpioResult r;
    auto* l = operable_line("wait_edge", r);
    if (l == nullptr) return r;
    if (l->edge == GpioEdge::none) return gpio_failure(kWaitWithoutEdges, EINVAL);
    if (!state_->changed.wait_for(lock, timeout, [&] { return !l->events.empty(); }))
      return GpioResult{GpioStatus::timeout, 0, "wait_edge"};
    event = l->events.front();
    l->events.pop_front();
    return r;
  }
};

State::Line& claim(State& s, const GpioLineConfig& c) {
  auto& l = s.line(c.chip, c.offset);
  if (!l.consumer.empty())
    throw GpioError(line_name(c) + " is busy (already requested by '" + l.consumer + "')", EBUSY);
  return l;
}

}  // namespace

FakeGpioLines::FakeGpioLines() : state_(std::make_shared<State>()) {}
FakeGpioLines::~FakeGpioLines() = default;

void FakeGpioLines::add_chip(const std::string& name, unsigned num_lines, const std::string& label) {
  std::lock_guard lock(state_->mutex);
  state_->chips[name] = State::Chip{label, std::vector<State::Line>(num_lines)};
}

std::unique_ptr<GpioOutputLine> FakeGpioLines::request_output(const GpioLineConfig& config, bool initial_value) {
  std::lock_guard lock(state_->mutex);
  auto& l = claim(*state_, config);
  l.consumer = config.consumer.empty() ? "?" : config.consumer;
  l.output = true;
  l.output_value = initial_value;
  return std::make_unique<FakeOutput>(state_, config);
}

std::unique_ptr<GpioInputLine> FakeGpioLines::request_input(const GpioLineConfig& config, GpioEdge edge,
                                                            GpioBias bias) {
  std::lock_guard lock(state_->mutex);
  auto& l = claim(*state_, config);
  l.consumer = config.consumer.empty() ? "?" : config.consumer;
  l.output = false;
  l.edge = edge;
  if (bias == GpioBias::pull_up) l.bias_pull_up = true;
  if (bias == GpioBias::pull_down) l.bias_pull_up = false;
  l.events.clear();
  return std::make_unique<FakeInput>(state_, config);
}

void FakeGpioLines::drive(const std::string& chip, unsigned offset, std::optional<bool> value) {
  std::lock_guard lock(state_->mutex);
  auto& l = state_->line(chip, offset);
  const bool before = State::level_of(l);
  l.driven = value;
  state_->record_edge(l, before);
}

void FakeGpioLines::set_pull(const std::string& chip, unsigned offset, bool up) {
  std::lock_guard lock(state_->mutex);
  auto& l = state_->line(chip, offset);
  const bool before = State::level_of(l);
  l.chip_pull_up = up;
  state_->record_edge(l, before);
}

bool FakeGpioLines::level(const std::string& chip, unsigned offset) const {
  std::lock_guard lock(state_->mutex);
  return State::level_of(state_->line(chip, offset));
}

std::string FakeGpioLines::consumer(const std::string& chip, unsigned offset) const {
  std::lock_guard lock(state_->mutex);
  return state_->line(chip, offset).consumer;
}

void FakeGpioLines::fail_operations(const std::string& chip, unsigned offset, bool failing) {
  std::lock_guard lock(state_->mutex);
  state_->line(chip, offset).failing = failing;
  state_->changed.notify_all();
}

}  // namespace swum::io
