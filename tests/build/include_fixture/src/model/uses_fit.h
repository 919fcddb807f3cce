// Fixture of build.include_check_sees_breaks: the model may not use a fitting room.
#pragma once

#include "analysis/fit/fit_thing.h"
