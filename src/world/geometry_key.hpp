#pragma once
// Keys for sharing shapes' geometries: a geometry's used fields, byte for byte, in one
// string. Both worlds store one copy of each polygon (2D) or hull (3D) for all the shapes
// that are equal to the bit (BodyStore's and BodyStore3's SharedGeometries), so that a pile
// of one shape reads one copy, in cache, and validates it once. Private to the world layer.

#include <cstddef>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>
#include <unordered_map>

#include "quack/math/vec2.hpp"
#include "quack/math/vec3.hpp"

namespace quack::detail {

// Writes fields into a key of a size known beforehand (field by field: structs with
// padding, and arrays whose unused tails may hold anything, are never copied whole).
class KeyWriter {
 public:
  explicit KeyWriter(std::size_t size) : key_(size, '\0'), at_(key_.data()) {}
  template <class T>
  void put(const T& value) noexcept {
    static_assert(std::is_trivially_copyable_v<T>);
    std::memcpy(at_, &value, sizeof(T));
    at_ += sizeof(T);
  }
  template <class T>
  void put(const T* values, std::size_t count) noexcept {
    static_assert(std::is_trivially_copyable_v<T>);
    std::memcpy(at_, values, count * sizeof(T));
    at_ += count * sizeof(T);
  }
  void put(Vec2 v) noexcept {
    put(v.x);
    put(v.y);
  }
  void put(Vec3 v) noexcept {
    put(v.x);
    put(v.y);
    put(v.z);
  }
  // The key, once every byte announced to the constructor is written.
  std::string take() noexcept { return std::move(key_); }

 private:
  std::string key_;
  char* at_;
};

// Stored geometries by their keys, held weakly: an entry lives as long as some shape holds
// its geometry. Entries that expired are swept when the table has doubled since the last
// sweep, so a world that makes and drops many shapes does not keep their keys for ever.
template <class Stored>
class InternTable {
 public:
  // The stored geometry with this key, or null when there is none (or it expired).
  std::shared_ptr<const Stored> find(const std::string& key) const {
    const auto found = entries_.find(key);
    return found == entries_.end() ? nullptr : found->second.lock();
  }
  void insert(std::string key, const std::shared_ptr<const Stored>& stored) {
    entries_.insert_or_assign(std::move(key), stored);
    if (entries_.size() > 2 * swept_ + 64) {
      std::erase_if(entries_, [](const auto& kv) { return kv.second.expired(); });
      swept_ = entries_.size();
    }
  }

 private:
  std::unordered_map<std::string, std::weak_ptr<const Stored>> entries_;
  std::size_t swept_ = 0;
};

}  // namespace quack::detail
