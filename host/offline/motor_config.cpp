#include "offline/motor_config.h"

#include "formats/parameter_file.h"
#include "output/text_files.h"

namespace swum::host {

MotorParameters load_motor_parameters(const std::filesystem::path& path) {
  return parse_motor_parameters(read_text_file(path), path.string());
}

}  // namespace swum::host
