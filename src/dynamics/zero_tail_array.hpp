#pragma once
// ZeroTailArray<T>: a growable array of a trivially copyable T for the body
// store's per-body scratch that most bodies never write (forces[], applied[],
// scratch[]: the step writes them for awake bodies only, and a static or
// sleeping body's entry stays the zero value it was made with).
//
// Why: a std::vector writes every element it is given, so a million static
// bodies wrote 72 MB of zeros into these three arrays, each page of it a
// page fault in the kernel (large_world, issue 21: ~2 us a page on the
// benchmark machine, as much as the instructions of a body's creation).
// Here the storage comes from calloc, whose fresh pages read as zero without
// being written (the kernel maps them on first write), and the bytes past
// size() are kept zero, so appending an all-zero element writes nothing:
// only the pages of the entries a step writes are ever touched.
//
// Invariant: every byte of the storage at or past size() is zero (pop_back,
// resize and clear write zeros over what they drop). The values are those of
// a std::vector<T> in every case: an element whose value-initialised bytes
// are not all zero is written as a std::vector would write it.
//
// The subset of std::vector's interface the body store uses; growth is
// geometric for push_back and exact for reserve, as std::vector's.
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <new>
#include <type_traits>
#include <utility>

namespace fulcrum::detail {

template <class T>
class ZeroTailArray {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>,
                  "ZeroTailArray copies and drops elements as bytes");
    static_assert(alignof(T) <= alignof(std::max_align_t), "calloc's storage is aligned for max_align_t only");

public:
    ZeroTailArray() = default;
    ZeroTailArray(const ZeroTailArray& other) { copyFrom(other); }
    ZeroTailArray(ZeroTailArray&& other) noexcept
        : data_(std::exchange(other.data_, nullptr)),
          size_(std::exchange(other.size_, 0)),
          capacity_(std::exchange(other.capacity_, 0)) {}
    ZeroTailArray& operator=(const ZeroTailArray& other) {
        if (this != &other) {
            ZeroTailArray copy(other);
            swap(copy);
        }
        return *this;
    }
    ZeroTailArray& operator=(ZeroTailArray&& other) noexcept {
        ZeroTailArray moved(std::move(other));
        swap(moved);
        return *this;
    }
    ~ZeroTailArray() { std::free(data_); }

    void swap(ZeroTailArray& other) noexcept {
        std::swap(data_, other.data_);
        std::swap(size_, other.size_);
        std::swap(capacity_, other.capacity_);
    }

    std::size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    std::size_t capacity() const { return capacity_; }
    T* data() { return data_; }
    const T* data() const { return data_; }
    T& operator[](std::size_t i) { return data_[i]; }
    const T& operator[](std::size_t i) const { return data_[i]; }
    T& back() { return data_[size_ - 1]; }
    const T& back() const { return data_[size_ - 1]; }
    T* begin() { return data_; }
    T* end() { return data_ + size_; }
    const T* begin() const { return data_; }
    const T* end() const { return data_ + size_; }

    void reserve(std::size_t n) {
        if (n > capacity_) reallocate(n);
    }
    void push_back(const T& value) {
        if (size_ == capacity_) reallocate(capacity_ == 0 ? 1 : 2 * capacity_);
        // The slot reads as zero already: an all-zero value needs no write.
        if (!isZero(value)) std::memcpy(static_cast<void*>(data_ + size_), &value, sizeof(T));
        ++size_;
    }
    void pop_back() {
        --size_;
        std::memset(static_cast<void*>(data_ + size_), 0, sizeof(T));
    }
    // New elements are value-initialised (T{}), as std::vector's.
    void resize(std::size_t n) {
        if (n < size_) {
            std::memset(static_cast<void*>(data_ + n), 0, (size_ - n) * sizeof(T));
        } else if (n > size_) {
            reserve(n);
            const T zero{};
            if (!isZero(zero)) {
                for (std::size_t i = size_; i < n; ++i) std::memcpy(static_cast<void*>(data_ + i), &zero, sizeof(T));
            }
        }
        size_ = n;
    }
    void clear() { resize(0); }

    // Whether a value's bytes are all zero (then appending it writes nothing).
    static bool isZero(const T& value) {
        unsigned char bytes[sizeof(T)];
        std::memcpy(bytes, &value, sizeof(T));
        unsigned char any = 0;
        for (const unsigned char b : bytes) any |= b;
        return any == 0;
    }

private:
    void reallocate(std::size_t n) {
        // calloc: the new pages read as zero, and the kernel leaves them
        // untouched until they are written.
        T* fresh = static_cast<T*>(std::calloc(n, sizeof(T)));
        if (fresh == nullptr) throw std::bad_alloc();
        if (size_ != 0) std::memcpy(static_cast<void*>(fresh), data_, size_ * sizeof(T));
        std::free(data_);
        data_ = fresh;
        capacity_ = n;
    }
    void copyFrom(const ZeroTailArray& other) {
        if (other.size_ == 0) return;
        reallocate(other.size_);
        std::memcpy(static_cast<void*>(data_), other.data_, other.size_ * sizeof(T));
        size_ = other.size_;
    }

    T* data_ = nullptr;
    std::size_t size_ = 0;
    std::size_t capacity_ = 0;
};

}  // namespace fulcrum::detail
