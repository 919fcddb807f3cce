// Fixture of build.include_check_sees_breaks: the emulator may not use a fitting room.
#include "analysis/fit/fit_thing.h"
