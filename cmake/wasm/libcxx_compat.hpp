#pragma once
// Included before every source of the WebAssembly build only
// (scripts/build-wasm.sh: -include): the C++17/20 library pieces Fulcrum
// uses that Emscripten 3.1.6's libc++ lacks: std::bit_cast and
// std::atomic_ref (with the compiler's builtins, for exactly the operations
// Fulcrum calls: load, store, fetch_or, compare_exchange_weak and _strong),
// and std::to_chars of a float or double in its shortest round-trip form
// (the same text as the standard's: fixed or scientific, whichever is
// shorter, fixed on a tie). Never seen by the native builds, whose
// libstdc++ has them all.
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <version>

#if !defined(__cpp_lib_bit_cast)
namespace std {
template <class To, class From>
constexpr To bit_cast(const From& from) noexcept {
    return __builtin_bit_cast(To, from);
}
}  // namespace std
#endif

#if !defined(__cpp_lib_atomic_ref)
namespace std {
template <class T>
class atomic_ref {
public:
    explicit atomic_ref(T& value) : p_(&value) {}
    T load(memory_order order = memory_order_seq_cst) const { return __atomic_load_n(p_, builtin(order)); }
    void store(T value, memory_order order = memory_order_seq_cst) const { __atomic_store_n(p_, value, builtin(order)); }
    T fetch_or(T value, memory_order order = memory_order_seq_cst) const {
        return __atomic_fetch_or(p_, value, builtin(order));
    }
    bool compare_exchange_weak(T& expected, T desired, memory_order order = memory_order_seq_cst) const {
        return __atomic_compare_exchange_n(p_, &expected, desired, true, builtin(order), failure(order));
    }
    bool compare_exchange_strong(T& expected, T desired, memory_order order = memory_order_seq_cst) const {
        return __atomic_compare_exchange_n(p_, &expected, desired, false, builtin(order), failure(order));
    }

private:
    static constexpr int builtin(memory_order order) {
        switch (order) {
            case memory_order_relaxed: return __ATOMIC_RELAXED;
            case memory_order_consume: return __ATOMIC_CONSUME;
            case memory_order_acquire: return __ATOMIC_ACQUIRE;
            case memory_order_release: return __ATOMIC_RELEASE;
            case memory_order_acq_rel: return __ATOMIC_ACQ_REL;
            default: return __ATOMIC_SEQ_CST;
        }
    }
    // A failed exchange only loads: no release part.
    static constexpr int failure(memory_order order) {
        if (order == memory_order_acq_rel) return __ATOMIC_ACQUIRE;
        if (order == memory_order_release) return __ATOMIC_RELAXED;
        return builtin(order);
    }
    T* p_;
};
}  // namespace std
#endif

#if (defined(__EMSCRIPTEN__) && !defined(__cpp_lib_to_chars)) || defined(FULCRUM_WASM_COMPAT_TEST)
namespace fulcrum_wasm_compat {
// The shortest digits that read back as v (printf's %e is exact), then laid
// out as the standard's to_chars does.
template <class T>
std::to_chars_result shortestToChars(char* first, char* last, T v) {
    char text[64];
    int n = 0;
    if (v == 0) {
        n = std::snprintf(text, sizeof text, std::signbit(v) ? "-0" : "0");
    } else {
        constexpr int kMaxDigits = sizeof(T) == sizeof(float) ? 9 : 17;
        char sci[40];
        for (int digits = 1; digits <= kMaxDigits; ++digits) {
            std::snprintf(sci, sizeof sci, "%.*e", digits - 1, static_cast<double>(v));
            const T back = sizeof(T) == sizeof(float) ? static_cast<T>(std::strtof(sci, nullptr))
                                                      : static_cast<T>(std::strtod(sci, nullptr));
            if (back == v) break;
        }
        // sci: [-]d[.ddd]e(+|-)XX
        const bool negative = sci[0] == '-';
        const char* p = sci + (negative ? 1 : 0);
        char digitText[24];
        int count = 0;
        for (; *p != 'e'; ++p) {
            if (*p != '.') digitText[count++] = *p;
        }
        const int exponent = std::atoi(p + 1);
        char fixed[400];
        int f = 0;
        if (negative) fixed[f++] = '-';
        if (exponent >= count - 1) {
            // An integer: the standard's text is printf's %.0f, its exact digits
            // (as long as the shortest digits padded with zeros).
            f = std::snprintf(fixed, sizeof fixed, "%.0f", static_cast<double>(v));
        } else if (exponent >= 0) {
            for (int i = 0; i < count; ++i) {
                fixed[f++] = digitText[i];
                if (i == exponent) fixed[f++] = '.';
            }
        } else {
            fixed[f++] = '0';
            fixed[f++] = '.';
            for (int i = 0; i < -exponent - 1; ++i) fixed[f++] = '0';
            for (int i = 0; i < count; ++i) fixed[f++] = digitText[i];
        }
        const int sciLength = static_cast<int>(std::strlen(sci));
        if (f <= sciLength) {
            std::memcpy(text, fixed, static_cast<std::size_t>(f));
            n = f;
        } else {
            std::memcpy(text, sci, static_cast<std::size_t>(sciLength));
            n = sciLength;
        }
    }
    if (last - first < n) return {last, std::errc::value_too_large};
    std::memcpy(first, text, static_cast<std::size_t>(n));
    return {first + n, std::errc()};
}
}  // namespace fulcrum_wasm_compat
#endif
#if defined(__EMSCRIPTEN__) && !defined(__cpp_lib_to_chars)
namespace std {
inline to_chars_result to_chars(char* first, char* last, double v) {
    return fulcrum_wasm_compat::shortestToChars(first, last, v);
}
inline to_chars_result to_chars(char* first, char* last, float v) {
    return fulcrum_wasm_compat::shortestToChars(first, last, v);
}
}  // namespace std
#endif
