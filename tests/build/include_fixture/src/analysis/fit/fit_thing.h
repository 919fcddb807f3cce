// Fixture of build.include_check_sees_breaks: a header of the fit room.
#pragma once
