// Values as bytes, bit for bit, in the host's byte order: what a shard file holds and what MPI
// ranks send each other (run/shard.hpp, truth/point_bytes.hpp). A reader refuses bytes that end
// early or hold what no writer writes with one line naming their source.
#pragma once

#include "common/input.hpp"

#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace pldamp::harness {

class ByteWriter {
public:
  explicit ByteWriter(std::string& bytes) : bytes_(bytes) {}
  template <class T>
  requires std::is_arithmetic_v<T>
  void put(T value) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    bytes_.append(raw, sizeof(T));
  }
  void put_raw(const void* value, std::size_t size) {
    bytes_.append(static_cast<const char*>(value), size);
  }
  void put(std::string_view text) {
    put<std::uint64_t>(text.size());
    bytes_.append(text);
  }
  void put(const std::optional<double>& value) {
    put<std::uint8_t>(value ? 1 : 0);
    if (value) {
      put(*value);
    }
  }
  void put(const std::vector<std::optional<double>>& values) {
    put<std::uint64_t>(values.size());
    for (const std::optional<double>& value : values) {
      put(value);
    }
  }

private:
  std::string& bytes_;
};

class ByteReader {
public:
  ByteReader(std::string_view bytes, const std::string& source) : bytes_(bytes), source_(source) {}
  template <class T>
  requires std::is_arithmetic_v<T> T get() {
    T value;
    std::memcpy(&value, take(sizeof(T)).data(), sizeof(T));
    return value;
  }
  void get_raw(void* value, std::size_t size) { std::memcpy(value, take(size).data(), size); }
  std::string string() { return std::string(take(size())); }
  // A string a writer of report files may hold: at most `max_bytes`, and UTF-8 (a shard's text
  // that is not reached report.json's writer as an internal error).
  std::string text(std::size_t max_bytes) {
    const std::size_t length = size();
    if (length > max_bytes) {
      corrupt();
    }
    std::string out(take(length));
    if (!valid_utf8(out)) {
      corrupt();
    }
    return out;
  }
  std::optional<double> optional() {
    const auto flag = get<std::uint8_t>();
    if (flag > 1) {
      corrupt();
    }
    return flag == 1 ? std::optional<double>(get<double>()) : std::nullopt;
  }
  std::vector<std::optional<double>> optionals() {
    std::vector<std::optional<double>> values(size(1)); // a flag byte each at least
    for (std::optional<double>& value : values) {
      value = optional();
    }
    return values;
  }
  // A count of items of at least `least_bytes` each, no more than the bytes left could hold: a
  // corrupt count allocates nothing (a count of strings of a 4 MB file, checked against its bytes
  // but not their 8-byte lengths, once allocated 145 MB of empty strings before the refusal).
  std::size_t size(std::size_t least_bytes = 1) {
    const auto count = get<std::uint64_t>();
    if (count > (bytes_.size() - at_) / least_bytes) {
      corrupt();
    }
    return static_cast<std::size_t>(count);
  }
  bool at_end() const { return at_ == bytes_.size(); }
  std::string_view rest() const { return bytes_.substr(at_); } // the bytes not read yet
  [[noreturn]] void corrupt() const {
    throw InputError(source_ + " is truncated or corrupt: it is not a file pldamp wrote");
  }

private:
  std::string_view take(std::size_t n) {
    if (n > bytes_.size() - at_) {
      corrupt();
    }
    const std::string_view part = bytes_.substr(at_, n);
    at_ += n;
    return part;
  }
  std::string_view bytes_;
  std::size_t at_ = 0;
  const std::string& source_;
};

} // namespace pldamp::harness
