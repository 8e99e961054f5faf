#pragma once
// The message of the fulcrum::Error that f() throws ("(no error)" if none), for
// tests that compare whole messages.
#include <string>

#include "fulcrum/error.hpp"

namespace fulcrum::test {

template <class F>
std::string errorOf(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace fulcrum::test
