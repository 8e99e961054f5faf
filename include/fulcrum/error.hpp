#pragma once
// Every error the public API reports is a fulcrum::Error whose message names
// the object and the field and says what is wrong ("body 'crate': mass must be
// positive, got -1"). Internals never throw: they trust validated data.
#include <stdexcept>
#include <string>

namespace fulcrum {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace fulcrum
