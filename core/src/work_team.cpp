#include "dc/core/work_team.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <chrono>
#include <utility>

namespace dc {
namespace {

thread_local bool tls_inside = false;  // this thread runs a team's body (any member)

std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

bool WorkTeam::inside() { return tls_inside; }

WorkTeam::~WorkTeam() {
  stopping_.store(true);
  start_.notify();
  for (std::thread& t : helpers_) t.join();
}

void WorkTeam::grow(int helpers) {
  helpers = std::min(helpers, kMaxHelpers);
  if (!gates_) gates_ = std::make_unique<Gate[]>(kMaxHelpers);
  // A new helper's gate is closed up to the current run, so it joins only later ones.
  while (static_cast<int>(helpers_.size()) < helpers) {
    const int member = static_cast<int>(helpers_.size()) + 1;
    gates_[static_cast<size_t>(member - 1)].tag.store(2 * run_.load() + 2);
    helpers_.emplace_back([this, member] { helper_loop(member); });
  }
}

void WorkTeam::helper_loop(int member) {
  Gate& gate = gates_[static_cast<size_t>(member - 1)];
  std::int64_t last = run_.load();
  for (;;) {
    // Idle: sleeps of up to 100 ms (a missed wake-up only leaves this helper out of a run).
    start_.wait([&] { return run_.load() > last || stopping_.load(); }, 100000);
    if (stopping_.load()) return;
    const std::int64_t r = run_.load();
    last = r;
    // Join run r unless the calling thread closed it to this helper already.
    std::int64_t tag = gate.tag.load();
    bool joined = false;
    while (tag < 2 * r + 1 && !joined) joined = gate.tag.compare_exchange_weak(tag, 2 * r + 1);
    if (!joined) continue;
    const bool traced = trace_ != nullptr && member == 1;
    if (traced) current_.helper_start = now_ns();
    tls_inside = true;
    try {
      (*body_)(member);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex_);
      if (!error_) error_ = std::current_exception();
    }
    tls_inside = false;
    if (traced) current_.helper_done = now_ns();
    gate.tag.store(2 * r + 2);
    done_.notify();
  }
}

void WorkTeam::close(int member, std::int64_t run) {
  Gate& gate = gates_[static_cast<size_t>(member - 1)];
  std::int64_t tag = gate.tag.load();
  for (;;) {
    if (tag >= 2 * run + 2) return;
    if (tag == 2 * run + 1) {  // joined: wait until it returns
      done_.wait([&] { return gate.tag.load() >= 2 * run + 2; });
      return;
    }
    if (gate.tag.compare_exchange_weak(tag, 2 * run + 2)) return;
  }
}

void WorkTeam::gather(int threads, PartJob body) {
  threads = std::min(threads, kMaxHelpers + 1);
  if (threads <= 1 || inside()) {
    body(0);
    return;
  }
  grow(threads - 1);
  const std::int64_t r = run_.load() + 1;
  // Helpers beyond this run's members are closed before it starts; no helper is in a run now.
  for (int m = threads; m <= static_cast<int>(helpers_.size()); ++m)
    gates_[static_cast<size_t>(m - 1)].tag.store(2 * r + 2);
  body_ = &body;
  error_ = nullptr;
  if (trace_ != nullptr) current_ = TeamRunTrace{now_ns()};
  run_.store(r);
  const bool woke = start_.notify();
  tls_inside = true;
  try {
    body(0);
  } catch (...) {
    const std::lock_guard<std::mutex> lock(error_mutex_);
    if (!error_) error_ = std::current_exception();
  }
  tls_inside = false;
  const std::int64_t caller_done = trace_ != nullptr ? now_ns() : 0;
  for (int m = 1; m < threads; ++m) close(m, r);
  body_ = nullptr;
  if (trace_ != nullptr) {
    current_.caller_done = caller_done;
    current_.end = now_ns();
    current_.woke = woke;
    trace_->push_back(current_);
  }
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

namespace {

/// for_parts' claims: the parts split into one contiguous block per member; a member takes its
/// own block's parts from the front, then the other blocks' parts from the back (the parts of a
/// member that is late or never joins are done by the others). While the members keep pace, a
/// member runs the same parts run after run, so each core writes and reads the same share of a
/// stage's arrays from step to step.
class PartClaims {
 public:
  static constexpr int kMostMembers = 64;  // gather's most members: the caller and 63 helpers

  PartClaims(int parts, int members) : parts_(parts), members_(members) {}

  /// The next part for `member`; false when every part is taken.
  bool next(int member, int& part) {
    for (int j = 0; j < members_; ++j)
      if (claim((member + j) % members_, j != 0, part)) return true;
    return false;
  }

 private:
  [[nodiscard]] int first(int block) const {
    return static_cast<int>(static_cast<long>(parts_) * block / members_);
  }

  bool claim(int block, bool from_back, int& part) {
    std::atomic<std::uint64_t>& taken = taken_[static_cast<size_t>(block)].word;  // front << 32 | back
    const int lo = first(block), hi = first(block + 1);
    std::uint64_t w = taken.load();
    for (;;) {
      const int front = static_cast<int>(w >> 32), back = static_cast<int>(w & 0xffffffffU);
      if (front + back >= hi - lo) return false;
      if (taken.compare_exchange_weak(w, w + (from_back ? 1 : std::uint64_t{1} << 32))) {
        part = from_back ? hi - 1 - back : lo + front;
        return true;
      }
    }
  }

  struct alignas(64) Taken {
    std::atomic<std::uint64_t> word{0};
  };
  int parts_, members_;
  std::array<Taken, kMostMembers> taken_;
};

}  // namespace

void WorkTeam::for_parts(int threads, int parts, PartJob job) {
  if (threads <= 1 || parts <= 1 || inside()) {
    for (int p = 0; p < parts; ++p) job(p);
    return;
  }
  const int members = std::min({threads, parts, PartClaims::kMostMembers});
  PartClaims claims(parts, members);
  gather(members, [&](int member) {
    for (int p = 0; claims.next(member, p);) job(p);
  });
}

WorkTeam& calling_thread_team() {
  thread_local WorkTeam team;
  return team;
}

}  // namespace dc
