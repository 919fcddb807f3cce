# Installation and the Debian packages (docs/install.md), included by the top CMakeLists.txt.
#   cmake --install build/release [--prefix DIR]     the files below
#   (cd build/release && cpack)                      swum-hil_V-1_amd64.deb, python3-swum-bench_V-1_all.deb
# Two components: `runtime` (package swum-hil: the programs, their data, man pages, docs) and
# `bench` (package python3-swum-bench: the pytest plugin, with its entry point).

set(SWUM_DEBIAN_RELEASE 1)
set(SWUM_PACKAGE_NAME swum-hil)
set(SWUM_BENCH_PACKAGE_NAME python3-swum-bench)
set(SWUM_DATA_INSTALL_DIR ${CMAKE_INSTALL_DATADIR}/swum-hil)
set(_packaging ${PROJECT_SOURCE_DIR}/tools/packaging)
set(_out ${PROJECT_BINARY_DIR}/packaging)

# The version's one source is project(VERSION); CHANGELOG.md's first entry must name it.
file(STRINGS ${PROJECT_SOURCE_DIR}/CHANGELOG.md _entries REGEX "^## " ENCODING UTF-8)
list(GET _entries 0 _newest)
if(NOT _newest MATCHES "^## ([0-9]+\\.[0-9]+\\.[0-9]+) — ([0-9]+-[0-9]+-[0-9]+)$")
  message(FATAL_ERROR "CHANGELOG.md: the first entry '${_newest}' is not '## X.Y.Z — YYYY-MM-DD'")
endif()
if(NOT CMAKE_MATCH_1 STREQUAL PROJECT_VERSION)
  message(FATAL_ERROR "CHANGELOG.md: the newest entry is ${CMAKE_MATCH_1}, project(VERSION) is ${PROJECT_VERSION}")
endif()
set(SWUM_RELEASE_DATE ${CMAKE_MATCH_2})
execute_process(COMMAND date -u -R -d "${SWUM_RELEASE_DATE} 00:00:00" OUTPUT_VARIABLE SWUM_RELEASE_DATE_RFC2822
                OUTPUT_STRIP_TRAILING_WHITESPACE COMMAND_ERROR_IS_FATAL ANY)

# --- runtime: programs, data, docs, man pages ----------------------------------------------------
install(TARGETS swum swum-emu RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
# The motors, the population's spreads, the scenarios and the protocol definitions (register
# map, DBC, EDS): the data directory both programs and the bench find by themselves.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/config/ DESTINATION ${SWUM_DATA_INSTALL_DIR} COMPONENT runtime)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${SWUM_PACKAGE_NAME}
        COMPONENT runtime)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${SWUM_PACKAGE_NAME}/docs
        COMPONENT runtime)

# Debian's copyright file and changelog (changelog.Debian.gz, compressed reproducibly) in each
# package's documentation folder.
configure_file(${_packaging}/changelog.Debian.in ${_out}/runtime/changelog.Debian @ONLY)
set(SWUM_PACKAGE_NAME_SAVED ${SWUM_PACKAGE_NAME})
set(SWUM_PACKAGE_NAME ${SWUM_BENCH_PACKAGE_NAME})
configure_file(${_packaging}/changelog.Debian.in ${_out}/bench/changelog.Debian @ONLY)
set(SWUM_PACKAGE_NAME ${SWUM_PACKAGE_NAME_SAVED})
# CHANGELOG.md as Debian names an upstream changelog (changelog.gz).
add_custom_command(OUTPUT ${_out}/runtime/changelog.gz
                   COMMAND gzip -9nc ${PROJECT_SOURCE_DIR}/CHANGELOG.md > ${_out}/runtime/changelog.gz
                   DEPENDS ${PROJECT_SOURCE_DIR}/CHANGELOG.md)
set(_generated ${_out}/runtime/changelog.gz ${_out}/runtime/changelog.Debian.gz ${_out}/bench/changelog.Debian.gz)
foreach(component runtime bench)
  add_custom_command(OUTPUT ${_out}/${component}/changelog.Debian.gz
                     COMMAND gzip -9nkf ${_out}/${component}/changelog.Debian
                     DEPENDS ${_out}/${component}/changelog.Debian VERBATIM)
endforeach()

# A man page per program, from its --help and --version (help2man, at build time).
# Not in the sanitizer and fuzz builds, whose programs are not installed (and whose runtime
# reports at exit are the tests' business, not the build's).
find_program(SWUM_HELP2MAN help2man)
if(SWUM_HELP2MAN AND NOT SWUM_SANITIZE AND NOT SWUM_FUZZ)
  foreach(program swum swum-emu)
    if(program STREQUAL swum)
      set(_name "ultrasonic motor model, emulator client and operating-point tool")
    else()
      set(_name "two-phase ultrasonic-motor amplifier and motor emulator")
    endif()
    add_custom_command(OUTPUT ${_out}/man/${program}.1.gz
                       COMMAND ${CMAKE_COMMAND} -E make_directory ${_out}/man
                       COMMAND ${SWUM_HELP2MAN} --no-info --no-discard-stderr --section=1 --name=${_name}
                               --output=${_out}/man/${program}.1 $<TARGET_FILE:${program}>
                       COMMAND gzip -9nf ${_out}/man/${program}.1
                       DEPENDS ${program} VERBATIM)
    list(APPEND _generated ${_out}/man/${program}.1.gz)
    install(FILES ${_out}/man/${program}.1.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT runtime)
  endforeach()
else()
  message(STATUS "no man pages in this build (help2man missing - tools/setup installs it - or a sanitizer build)")
endif()
add_custom_target(swum_package_files ALL DEPENDS ${_generated})
install(FILES ${_packaging}/copyright ${_out}/runtime/changelog.Debian.gz ${_out}/runtime/changelog.gz
        DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${SWUM_PACKAGE_NAME} COMPONENT runtime)

# --- bench: the pytest plugin, found by pytest through its entry point ---------------------------
set(SWUM_PYTHON_INSTALL_DIR lib/python3/dist-packages CACHE STRING "where the bench's Python package is installed")
install(DIRECTORY ${PROJECT_SOURCE_DIR}/bench/swum_bench DESTINATION ${SWUM_PYTHON_INSTALL_DIR} COMPONENT bench
        PATTERN __pycache__ EXCLUDE)
# The distribution's metadata as pip would write it: pytest loads plugins named in the
# `pytest11` entry points of installed distributions (bench/pyproject.toml declares the same).
set(_dist ${_out}/bench/swum_bench-${PROJECT_VERSION}.dist-info)
file(WRITE ${_dist}/METADATA "Metadata-Version: 2.1\nName: swum-bench\nVersion: ${PROJECT_VERSION}\n"
     "Summary: pytest plugin: test a motor controller against swum-emu, the virtual ultrasonic motor\n"
     "License: Apache-2.0\nRequires-Python: >=3.11\n")
# Named as `-p swum_bench.plugin` names it, so that a checkout's tools/bench (which passes -p)
# and the installed entry point are one plugin, not two registrations of one module.
file(WRITE ${_dist}/entry_points.txt "[pytest11]\nswum_bench.plugin = swum_bench.plugin\n")
file(WRITE ${_dist}/top_level.txt "swum_bench\n")
file(WRITE ${_dist}/INSTALLER "debian\n")
install(DIRECTORY ${_dist} DESTINATION ${SWUM_PYTHON_INSTALL_DIR} COMPONENT bench)
install(FILES ${_packaging}/copyright ${_out}/bench/changelog.Debian.gz
        DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${SWUM_BENCH_PACKAGE_NAME} COMPONENT bench)

# --- CPack: the two Debian packages --------------------------------------------------------------
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME ${SWUM_PACKAGE_NAME})
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "swum-hil developers")
set(CPACK_PACKAGE_CONTACT "swum-hil developers <swum-hil@users.noreply.github.com>")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_COMPONENTS_ALL runtime bench)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_RELEASE ${SWUM_DEBIAN_RELEASE})
set(CPACK_DEBIAN_PACKAGE_SECTION electronics)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "https://github.com/swum-hil/swum-hil")
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME ${SWUM_PACKAGE_NAME})
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SHLIBDEPS ON)  # Depends from the libraries the programs link (dpkg-shlibdeps)
string(CONCAT CPACK_COMPONENT_RUNTIME_DESCRIPTION
    "emulator of a bimodal standing-wave ultrasonic motor behind its amplifier\n"
    "swum-emu runs the nonlinear whole-machine model of a bimodal standing-wave\n"
    "ultrasonic motor (Li et al., MSSP 2019) in a fixed-step real-time loop behind\n"
    "the interfaces of a two-phase amplifier: Modbus TCP/RTU, CAN (its own frames\n"
    "or CANopen CiA 301/402), GPIO and HTTP. swum logs, sweeps, picks the\n"
    "resonance-drift-aware operating frequency, controls, tracks and fits the model.")
set(CPACK_DEBIAN_BENCH_PACKAGE_NAME ${SWUM_BENCH_PACKAGE_NAME})
set(CPACK_DEBIAN_BENCH_PACKAGE_ARCHITECTURE all)
set(CPACK_DEBIAN_BENCH_PACKAGE_SECTION python)
set(CPACK_DEBIAN_BENCH_PACKAGE_DEPENDS
    "python3 (>= 3.11), python3-pytest, python3-numpy, python3-matplotlib, ${SWUM_PACKAGE_NAME} (= ${PROJECT_VERSION}-${SWUM_DEBIAN_RELEASE})")
# Byte-code written by importing the plugin is removed with the package (postinst/prerm).
set(CPACK_DEBIAN_BENCH_PACKAGE_CONTROL_EXTRA ${_packaging}/bench/postinst ${_packaging}/bench/prerm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_DEBIAN_BENCH_PACKAGE_RECOMMENDS "python3-pytest-xdist, python3-can, python3-canmatrix, python3-serial-asyncio")
string(CONCAT CPACK_COMPONENT_BENCH_DESCRIPTION
    "pytest plugin to test a motor controller against swum-emu\n"
    "The swum_bench fixture starts swum-emu, the virtual ultrasonic motor, steps it\n"
    "in lockstep with the controller under test over Modbus, CAN or CANopen,\n"
    "captures its signals and asserts on them; a failing assertion attaches a plot.")
include(CPack)
