// Items handed from a reading thread to the one that compares them, a bounded number at a time:
// how diff and diff --exact read two reports side by side without holding either (their memory
// does not grow with the reports).
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

namespace pldamp::harness::diff {

// Thrown by a reader whose items nobody takes any more: it stops reading.
struct Abandoned {};
// The failure a reader ends with when the fast reader declined its report (not pldamp's layout,
// or a line it doubts): what was taken of it is dropped, and the general reader reads it again.
struct Doubted {};
inline bool doubted(const std::exception_ptr& failure) {
  try {
    std::rethrow_exception(failure);
  } catch (const Doubted&) {
    return true;
  } catch (...) {
    return false;
  }
}

template <typename Item>
class BoundedQueue {
public:
  // Waits for room; throws Abandoned once the taker has given up.
  void push(Item&& item) {
    std::unique_lock lock(mutex_);
    room_.wait(lock, [&] { return items_.size() < capacity || abandoned_; });
    if (abandoned_) {
      throw Abandoned{};
    }
    items_.push_back(std::move(item));
    ready_.notify_one();
  }
  // The reader's end: after the last item, or with the failure the taker is to rethrow.
  void close(std::exception_ptr failure = nullptr) {
    const std::lock_guard lock(mutex_);
    closed_ = true;
    failure_ = failure;
    ready_.notify_one();
  }
  // The taker's end: nothing will be taken any more.
  void abandon() {
    const std::lock_guard lock(mutex_);
    abandoned_ = true;
    room_.notify_one();
  }
  // The next item, or none at the end (rethrowing the reader's failure).
  std::optional<Item> pop() {
    std::unique_lock lock(mutex_);
    ready_.wait(lock, [&] { return !items_.empty() || closed_; });
    if (!items_.empty()) {
      std::optional<Item> item(std::move(items_.front()));
      items_.pop_front();
      room_.notify_one();
      return item;
    }
    if (failure_) {
      std::rethrow_exception(failure_);
    }
    return std::nullopt;
  }

private:
  static constexpr std::size_t capacity = 256;
  std::mutex mutex_;
  std::condition_variable ready_, room_;
  std::deque<Item> items_;
  bool closed_ = false, abandoned_ = false;
  std::exception_ptr failure_;
};

// Two reports read side by side, each by `read` on a thread of its own into its queue: a read
// that returns closes its queue, one that throws closes it with the failure (Doubted among them)
// for the taker to rethrow. The readers are released and joined by stop(), or when this ends.
template <typename Item>
class SideBySide {
public:
  using Read = std::function<void(BoundedQueue<Item>& into)>;
  SideBySide(const Read& read_old, const Read& read_new)
      : old_reader_(reader(read_old, old_)), new_reader_(reader(read_new, new_)) {}
  SideBySide(const SideBySide&) = delete;
  SideBySide& operator=(const SideBySide&) = delete;
  ~SideBySide() { stop(); }

  BoundedQueue<Item>& old_queue() { return old_; }
  BoundedQueue<Item>& new_queue() { return new_; }
  // Nothing more is taken: the readers stop, and what they wrote may be read.
  void stop() {
    old_.abandon();
    new_.abandon();
    for (std::thread* reader : {&old_reader_, &new_reader_}) {
      if (reader->joinable()) {
        reader->join();
      }
    }
  }

private:
  static std::thread reader(const Read& read, BoundedQueue<Item>& queue) {
    return std::thread([read, &queue] {
      try {
        read(queue);
        queue.close();
      } catch (const Abandoned&) {
        queue.close();
      } catch (...) {
        queue.close(std::current_exception());
      }
    });
  }
  BoundedQueue<Item> old_, new_;
  std::thread old_reader_, new_reader_;
};

} // namespace pldamp::harness::diff
