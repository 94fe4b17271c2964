#pragma once
// Typed indices (as in Drake): a BodyIndex cannot be passed where a JointIndex or FrameIndex is
// expected, and containers indexed by one kind refuse the others at compile time.
#include <cstddef>
#include <vector>

namespace mbgen {

template <typename Tag> class TypedIndex {
 public:
  constexpr TypedIndex() = default;
  constexpr explicit TypedIndex(int value) : value_(value) {}
  constexpr int value() const { return value_; }
  constexpr bool valid() const { return value_ >= 0; }
  constexpr bool operator==(TypedIndex o) const { return value_ == o.value_; }
  constexpr bool operator!=(TypedIndex o) const { return value_ != o.value_; }
  constexpr bool operator<(TypedIndex o) const { return value_ < o.value_; }

 private:
  int value_ = -1;
};

using BodyIndex = TypedIndex<struct BodyTag>;
using JointIndex = TypedIndex<struct JointTag>;
using FrameIndex = TypedIndex<struct FrameTag>;

/// The world (fixed base) is body 0; moving bodies are numbered so that a parent comes first.
inline constexpr BodyIndex kWorldBody{0};

/// A std::vector that is indexed only by one kind of typed index.
template <typename Index, typename T> class IndexedVector {
 public:
  IndexedVector() = default;
  explicit IndexedVector(std::size_t n, const T& value = T()) : items_(n, value) {}
  T& operator[](Index i) { return items_[static_cast<std::size_t>(i.value())]; }
  const T& operator[](Index i) const { return items_[static_cast<std::size_t>(i.value())]; }
  int size() const { return static_cast<int>(items_.size()); }
  void push_back(T value) { items_.push_back(std::move(value)); }
  void resize(std::size_t n, const T& value = T()) { items_.resize(n, value); }
  auto begin() { return items_.begin(); }
  auto end() { return items_.end(); }
  auto begin() const { return items_.begin(); }
  auto end() const { return items_.end(); }
  T& back() { return items_.back(); }
  bool operator==(const IndexedVector& o) const { return items_ == o.items_; }

 private:
  std::vector<T> items_;
};

}  // namespace mbgen
