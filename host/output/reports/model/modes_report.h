// What `swum modes` prints: the natural frequencies and modal constants of a motor, as text
// or as one JSON object (--json).
#pragma once

#include <string>

#include "model/motor_model.h"

namespace swum::host {

/// Every modal constant as a JSON object (pretty, ordered keys, '\n' at the end).
std::string modes_json(const ModalConstants& c);

/// The natural frequencies, the stator's size and the main modal constants, one per line.
std::string modes_text(const ModalConstants& c);

}  // namespace swum::host
