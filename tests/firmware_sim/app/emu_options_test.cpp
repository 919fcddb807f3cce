// swum-emu's command line without starting it: parse_emu_options (CLI11, --modbus-*-ms) and the
// conversions into the parts' configurations, with every refusal's exact text and exit code.
#include "app/emu_options.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>
#include "installation.h"
#include "test_paths.h"

namespace swum::emu {
namespace {

const std::string kConfig = swum::test::source_path("config/li2019.toml");

EmuOptions parse(std::vector<std::string> args) {
  args.insert(args.begin(), "swum-emu");
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  return parse_emu_options(static_cast<int>(argv.size()), argv.data());
}

// --config plus `args`.
EmuOptions parse_with_config(std::vector<std::string> args) {
  args.insert(args.begin(), {"--config", kConfig});
  return parse(std::move(args));
}

// What parse() ends with when the command line ends the program.
EmuCliExit cli_exit(std::vector<std::string> args) {
  try {
    parse(std::move(args));
  } catch (const EmuCliExit& e) {
    return e;
  }
  ADD_FAILURE() << "no EmuCliExit";
  return EmuCliExit(-1, "", "");
}

// The one-line message of the EmuOptionError that `f` throws.
template <typename F>
std::string option_error(F f) {
  try {
    f();
  } catch (const EmuOptionError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no EmuOptionError";
  return {};
}

std::string parse_error(std::vector<std::string> args) {
  return option_error([&] { parse_with_config(std::move(args)); });
}

EmuOptions with(void (*change)(EmuOptions&)) {
  EmuOptions o;
  o.config_path = kConfig;
  change(o);
  return o;
}

// The refusal of `convert` for the defaults with one field set to `value`.
template <typename T, typename V, typename Convert>
std::string refusal(T EmuOptions::*field, V value, Convert convert) {
  EmuOptions o;
  o.*field = value;
  return option_error([&] { convert(o); });
}

constexpr const char* kRunWithHelp = "Run with --help for more information.\n";

TEST(EmuOptions, DefaultsAreTheDocumentedOnes) {
  const EmuOptions o = parse_with_config({});
  EXPECT_EQ(o.config_path, kConfig);
  EXPECT_EQ(o.can_interface, "");
  EXPECT_EQ(o.can_node, 1);
  EXPECT_EQ(o.modbus_spec, "tcp://127.0.0.1:1502");
  EXPECT_EQ(o.modbus_unit, 1);
  EXPECT_EQ(o.modbus_idle_timeout_ms, 10000);
  EXPECT_EQ(o.modbus_frame_timeout_ms, 500);
  EXPECT_EQ(o.modbus_evict_idle_ms, 1000);
  EXPECT_EQ(o.gpio_spec, "");
  EXPECT_EQ(o.encoder_resolution_um, 10.0);
  EXPECT_EQ(o.encoder_max_rate_hz, 20000.0);
  EXPECT_EQ(o.tick_hz, 10000.0);
  EXPECT_EQ(o.duration_s, 0.0);
  EXPECT_EQ(o.speedup, 1.0);
  EXPECT_EQ(o.spin_us, 0.0);
  EXPECT_EQ(o.watchdog_ms, 100.0);
  EXPECT_EQ(o.telemetry_hz, 100.0);
  EXPECT_EQ(o.heartbeat_ms, 1000.0);
  EXPECT_EQ(o.frequency_min_hz, 30000.0);
  EXPECT_EQ(o.frequency_max_hz, 50000.0);
  EXPECT_EQ(o.max_amplitude_v, 600.0);
  EXPECT_EQ(o.load_max_n, 30.0);
  EXPECT_EQ(o.frequency_slew_hz_per_s, 1e6);
  EXPECT_EQ(o.amplitude_slew_v_per_s, 1e5);
  EXPECT_EQ(o.frequency_hz, 40000.0);
  EXPECT_EQ(o.phase_deg, 90.0);
  EXPECT_FALSE(o.realtime);
  EXPECT_EQ(o.cpu, -1);
  EXPECT_EQ(o.ready_fd, -1);
}

TEST(EmuOptions, EachOptionSetsItsField) {
  const EmuOptions o = parse_with_config({"--can",
                                          "vcan0",
                                          "--node",
                                          "42",
                                          "--modbus",
                                          "rtu:/dev/ttyUSB0:115200",
                                          "--modbus-unit",
                                          "247",
                                          "--modbus-idle-timeout-ms",
                                          "0",
                                          "--modbus-frame-timeout-ms",
                                          "86400000",
                                          "--modbus-evict-idle-ms",
                                          "250",
                                          "--gpio",
                                          "gpiochip1:enable=3,fault=4",
                                          "--encoder-resolution-um",
                                          "2.5",
                                          "--encoder-max-rate-hz",
                                          "5000",
                                          "--tick-hz",
                                          "2000",
                                          "--duration-s",
                                          "2.5",
                                          "--speedup",
                                          "0",
                                          "--spin-us",
                                          "50",
                                          "--watchdog-ms",
                                          "250",
                                          "--telemetry-hz",
                                          "2000",
                                          "--heartbeat-ms",
                                          "0",
                                          "--min-frequency-hz",
                                          "35000",
                                          "--max-frequency-hz",
                                          "45000",
                                          "--max-amplitude-v",
                                          "300",
                                          "--max-load-n",
                                          "5",
                                          "--frequency-slew-hz-per-s",
                                          "2e7",
                                          "--amplitude-slew-v-per-s",
                                          "0",
                                          "--frequency-hz",
                                          "41000",
                                          "--drive-phase-deg",
                                          "-90",
                                          "--rt",
                                          "--cpu",
                                          "1",
                                          "--ready-fd",
                                          "3"});
  EXPECT_EQ(o.can_interface, "vcan0");
  EXPECT_EQ(o.can_node, 42);
  EXPECT_EQ(o.modbus_spec, "rtu:/dev/ttyUSB0:115200");
  EXPECT_EQ(o.modbus_unit, 247);
  EXPECT_EQ(o.modbus_idle_timeout_ms, 0);
  EXPECT_EQ(o.modbus_frame_timeout_ms, 86400000);
  EXPECT_EQ(o.modbus_evict_idle_ms, 250);
  EXPECT_EQ(o.gpio_spec, "gpiochip1:enable=3,fault=4");
  EXPECT_EQ(o.encoder_resolution_um, 2.5);
  EXPECT_EQ(o.encoder_max_rate_hz, 5000.0);
  EXPECT_EQ(o.tick_hz, 2000.0);
  EXPECT_EQ(o.duration_s, 2.5);
  EXPECT_EQ(o.speedup, 0.0);
  EXPECT_EQ(o.spin_us, 50.0);
  EXPECT_EQ(o.watchdog_ms, 250.0);
  EXPECT_EQ(o.telemetry_hz, 2000.0);
  EXPECT_EQ(o.heartbeat_ms, 0.0);
  EXPECT_EQ(o.frequency_min_hz, 35000.0);
  EXPECT_EQ(o.frequency_max_hz, 45000.0);
  EXPECT_EQ(o.max_amplitude_v, 300.0);
  EXPECT_EQ(o.load_max_n, 5.0);
  EXPECT_EQ(o.frequency_slew_hz_per_s, 2e7);
  EXPECT_EQ(o.amplitude_slew_v_per_s, 0.0);
  EXPECT_EQ(o.frequency_hz, 41000.0);
  EXPECT_EQ(o.phase_deg, -90.0);
  EXPECT_TRUE(o.realtime);
  EXPECT_EQ(o.cpu, 1);
  EXPECT_EQ(o.ready_fd, 3);
}

TEST(EmuOptions, HelpGoesToStdoutWithExitZero) {
  const EmuCliExit e = cli_exit({"--help"});
  EXPECT_EQ(e.exit_code(), 0);
  EXPECT_EQ(e.err(), "");
  EXPECT_EQ(e.out().rfind("swum-emu: two-phase ultrasonic-motor amplifier + motor emulator (docs/emulator.md)\n"
                          "Usage: swum-emu [OPTIONS]\n",
                          0),
            0u)
      << e.out();
  EXPECT_NE(e.out().find("  --modbus-idle-timeout-ms MS=10000\n"), std::string::npos) << e.out();
  EXPECT_NE(e.out().find("  --frequency-slew-hz-per-s FLOAT:NONNEGATIVE=1e+06\n"), std::string::npos) << e.out();
}

// Retired spellings (issue 34) are not aliases: one line naming the new spelling, whatever else
// CLI11 found wrong first (here the missing --config); --help still prints the help.
TEST(EmuOptions, RetiredSpellingsNameTheirNewOnes) {
  EXPECT_EQ(option_error([] {
              parse({"--frequency", "41000"});
            }),
            "--frequency was renamed --frequency-hz (every frequency option carries its unit)");
  EXPECT_EQ(option_error([] {
              parse_with_config({"--frequency-min=35000"});
            }).rfind("--frequency-min was renamed --min-frequency-hz (", 0),
            0u);
  EXPECT_EQ(option_error([] {
              parse_with_config({"--tick-hz", "1000", "--duration", "2"});
            }).rfind("--duration was renamed --duration-s (", 0),
            0u);
  EXPECT_EQ(cli_exit({"--help", "--phase", "90"}).exit_code(), 0);
  EXPECT_EQ(parse_with_config({"--frequency-hz", "41000", "--drive-phase-deg", "-90"}).frequency_hz, 41000.0);
}

// Without --config the calibrated motor of the data directory runs (docs/install.md): this test
// binary is a build of the checkout, so that is the checkout's config/li2019.toml.
TEST(EmuOptions, WithoutConfigTheDataDirectorysDefaultMotorRuns) {
  ::unsetenv("SWUM_DATA_DIR");  // an installation's choice in the environment is not this test's
  const EmuOptions o = parse({});
  EXPECT_EQ(std::filesystem::path(o.config_path), std::filesystem::path(kConfig).lexically_normal());
  EXPECT_TRUE(o.config_is_default);
  EXPECT_FALSE(parse_with_config({}).config_is_default);
}

TEST(EmuOptions, VersionGoesToStdoutWithExitZero) {
  const EmuCliExit e = cli_exit({"--version"});
  EXPECT_EQ(e.exit_code(), 0);
  EXPECT_EQ(e.out().rfind("swum-emu " + std::string(swum::installation::version()), 0), 0u) << e.out();
  EXPECT_EQ(e.err(), "");
}

TEST(EmuOptions, UsageErrorsKeepCli11TextAndExitCode) {
  struct Case {
    std::vector<std::string> args;
    int exit_code;
    std::string first_line;
  };
  const std::vector<Case> cases = {
      {{"--config", "/nonexistent/motor.toml"}, 105, "--config: File does not exist: /nonexistent/motor.toml"},
      {{"--config", kConfig, "--config", kConfig}, 114, "--config: At Most 1 required but received 2"},
      {{"--config", kConfig, "--node", "0"}, 105, "--node: Value 0 not in range 1 to 127"},
      {{"--config", kConfig, "--node", "128"}, 105, "--node: Value 128 not in range 1 to 127"},
      {{"--config", kConfig, "--modbus-unit", "248"}, 105, "--modbus-unit: Value 248 not in range 1 to 247"},
      {{"--config", kConfig, "--tick-hz", "50"}, 105, "--tick-hz: Value 50 not in range 100.000000 to 100000.000000"},
      {{"--config", kConfig, "--telemetry-hz", "3000"},
       105,
       "--telemetry-hz: Value 3000 not in range 0.000000 to 2000.000000"},
      {{"--config", kConfig, "--encoder-max-rate-hz", "0.5"},
       105,
       "--encoder-max-rate-hz: Value 0.5 not in range 1.000000 to 1000000.000000"},
      {{"--config", kConfig, "--spin-us", "2e6"}, 105, "--spin-us: Value 2e6 not in range 0.000000 to 1000000.000000"},
      {{"--config", kConfig, "--max-frequency-hz", "abc"}, 104, "Could not convert: --max-frequency-hz = abc"},
      {{"--config", kConfig, "--foo"}, 109, "The following argument was not expected: --foo"},
      {{"--config", kConfig, "extra"}, 109, "The following argument was not expected: extra"},
  };
  for (const Case& c : cases) {
    const EmuCliExit e = cli_exit(c.args);
    EXPECT_EQ(e.exit_code(), c.exit_code) << c.first_line;
    EXPECT_EQ(e.out(), "");
    EXPECT_EQ(e.err(), c.first_line + "\n" + kRunWithHelp);
  }
  // Non-negative checks name the largest double as the upper end.
  for (const char* option :
       {"--duration-s", "--speedup", "--watchdog-ms", "--heartbeat-ms", "--frequency-slew-hz-per-s",
        "--amplitude-slew-v-per-s", "--encoder-resolution-um", "--cpu"}) {
    const EmuCliExit e = cli_exit({"--config", kConfig, option, "-1"});
    EXPECT_EQ(e.exit_code(), 105) << option;
    EXPECT_EQ(e.err().rfind(std::string(option) + ": Value -1 not in range 0.000000 to 1797693134862315708", 0), 0u)
        << e.err();
  }
}

TEST(EmuOptions, ModbusMillisecondsRefusedWithOptionAndText) {
  EXPECT_EQ(parse_error({"--modbus-idle-timeout-ms", "abc"}),
            "--modbus-idle-timeout-ms: 'abc' is not a whole number of milliseconds (0 to 86400000 ms)");
  EXPECT_EQ(parse_error({"--modbus-idle-timeout-ms", "-5"}),
            "--modbus-idle-timeout-ms: '-5' is out of range (0 to 86400000 ms)");
  EXPECT_EQ(parse_error({"--modbus-idle-timeout-ms", "1.5"}),
            "--modbus-idle-timeout-ms: '1.5' is not a whole number of milliseconds (0 to 86400000 ms)");
  EXPECT_EQ(parse_error({"--modbus-frame-timeout-ms", "0"}),
            "--modbus-frame-timeout-ms: '0' is out of range (1 to 86400000 ms)");
  EXPECT_EQ(parse_error({"--modbus-frame-timeout-ms", "500ms"}),
            "--modbus-frame-timeout-ms: '500ms' is not a whole number of milliseconds (1 to 86400000 ms)");
  EXPECT_EQ(parse_error({"--modbus-evict-idle-ms", "99999999999"}),
            "--modbus-evict-idle-ms: '99999999999' is out of range (0 to 86400000 ms)");
  EXPECT_EQ(parse_error({"--modbus-evict-idle-ms", ""}),
            "--modbus-evict-idle-ms: '' is not a whole number of milliseconds (0 to 86400000 ms)");
  // Checked in option order: the first bad one is reported.
  EXPECT_EQ(parse_error({"--modbus-evict-idle-ms", "x", "--modbus-frame-timeout-ms", "y"}),
            "--modbus-frame-timeout-ms: 'y' is not a whole number of milliseconds (1 to 86400000 ms)");
}

TEST(EmuOptions, AmplifierConfigInSiUnits) {
  const AmplifierConfig amp = amplifier_config(
      parse_with_config({"--watchdog-ms", "250", "--min-frequency-hz", "35000", "--max-frequency-hz", "45000",
                         "--max-amplitude-v", "300", "--max-load-n", "5", "--frequency-slew-hz-per-s", "2e7",
                         "--amplitude-slew-v-per-s", "0", "--frequency-hz", "41000", "--drive-phase-deg", "-90"}));
  EXPECT_DOUBLE_EQ(amp.watchdog_s, 0.25);
  EXPECT_EQ(amp.limits.min_frequency_hz, 35000.0);
  EXPECT_EQ(amp.limits.max_frequency_hz, 45000.0);
  EXPECT_EQ(amp.limits.max_amplitude_v, 300.0);
  EXPECT_EQ(amp.limits.max_abs_load_n, 5.0);
  EXPECT_EQ(amp.frequency_slew_hz_per_s, 2e7);
  EXPECT_EQ(amp.amplitude_slew_v_per_s, 0.0);
  // A default slew above the largest a command may ask for raises that limit; a smaller one not.
  EXPECT_EQ(amp.limits.max_frequency_slew_hz_per_s, 2e7);
  EXPECT_EQ(amp.limits.max_amplitude_slew_v_per_s, 1e7);
  EXPECT_EQ(amp.frequency_hz, 41000.0);
  EXPECT_EQ(amp.phase_deg, -90.0);
  EXPECT_EQ(amp.amplitude_v, 0.0);
}

TEST(EmuOptions, DefaultAmplifierConfigIsTheAmplifiersOwn) {
  const AmplifierConfig amp = amplifier_config(parse_with_config({}));
  const AmplifierConfig own;
  EXPECT_DOUBLE_EQ(amp.watchdog_s, own.watchdog_s);
  EXPECT_EQ(amp.limits.min_frequency_hz, own.limits.min_frequency_hz);
  EXPECT_EQ(amp.limits.max_frequency_hz, own.limits.max_frequency_hz);
  EXPECT_EQ(amp.limits.max_amplitude_v, own.limits.max_amplitude_v);
  EXPECT_EQ(amp.limits.max_abs_phase_deg, own.limits.max_abs_phase_deg);
  EXPECT_EQ(amp.limits.max_abs_load_n, own.limits.max_abs_load_n);
  EXPECT_EQ(amp.limits.max_frequency_slew_hz_per_s, own.limits.max_frequency_slew_hz_per_s);
  EXPECT_EQ(amp.limits.max_amplitude_slew_v_per_s, own.limits.max_amplitude_slew_v_per_s);
  EXPECT_EQ(amp.frequency_slew_hz_per_s, own.frequency_slew_hz_per_s);
  EXPECT_EQ(amp.amplitude_slew_v_per_s, own.amplitude_slew_v_per_s);
  EXPECT_EQ(amp.frequency_hz, own.frequency_hz);
  EXPECT_EQ(amp.phase_deg, own.phase_deg);
}

TEST(EmuOptions, ConflictingOrOutOfLimitSetpointsRefused) {
  EXPECT_EQ(refusal(&EmuOptions::frequency_min_hz, 60000.0, amplifier_config),
            "--min-frequency-hz is above --max-frequency-hz");
  EXPECT_EQ(option_error([] {
              amplifier_config(with([](EmuOptions& o) {
                o.frequency_max_hz = 39000.0;
                o.frequency_min_hz = 39500.0;
              }));
            }),
            "--min-frequency-hz is above --max-frequency-hz");
  const std::string initial = "initial --frequency-hz / --drive-phase-deg outside the accepted limits";
  EXPECT_EQ(refusal(&EmuOptions::frequency_hz, 20000.0, amplifier_config), initial);
  EXPECT_EQ(refusal(&EmuOptions::frequency_hz, 50001.0, amplifier_config), initial);
  EXPECT_EQ(refusal(&EmuOptions::phase_deg, 200.0, amplifier_config), initial);
  EXPECT_EQ(refusal(&EmuOptions::phase_deg, -181.0, amplifier_config), initial);
  // Raising --min-frequency-hz above the default initial frequency needs --frequency-hz too.
  EXPECT_EQ(refusal(&EmuOptions::frequency_min_hz, 41000.0, amplifier_config), initial);
  // At the limits is accepted.
  EXPECT_NO_THROW(amplifier_config(with([](EmuOptions& o) {
    o.frequency_min_hz = o.frequency_max_hz = o.frequency_hz = 41000.0;
    o.phase_deg = -180.0;
  })));
}

TEST(EmuOptions, ModbusEndpoint) {
  EXPECT_FALSE(modbus_endpoint(with([](EmuOptions& o) { o.modbus_spec = "none"; })).has_value());
  const auto tcp = modbus_endpoint(parse_with_config({}));
  ASSERT_TRUE(tcp.has_value());
  EXPECT_TRUE(tcp->tcp);
  EXPECT_EQ(tcp->host, "127.0.0.1");
  EXPECT_EQ(tcp->port, 1502);
  const auto any = modbus_endpoint(with([](EmuOptions& o) { o.modbus_spec = "tcp://0.0.0.0:0"; }));
  ASSERT_TRUE(any.has_value());
  EXPECT_EQ(any->host, "0.0.0.0");
  EXPECT_EQ(any->port, 0);
  const auto rtu = modbus_endpoint(with([](EmuOptions& o) { o.modbus_spec = "rtu:/dev/ttyUSB0:115200"; }));
  ASSERT_TRUE(rtu.has_value());
  EXPECT_FALSE(rtu->tcp);
  EXPECT_EQ(rtu->device, "/dev/ttyUSB0");
  EXPECT_EQ(rtu->baud, 115200);
}

TEST(EmuOptions, BadModbusEndpointRefused) {
  const auto error = [](const char* spec) { return refusal(&EmuOptions::modbus_spec, spec, modbus_endpoint); };
  EXPECT_EQ(error("bogus"), "--modbus: expected tcp://HOST:PORT or rtu:/dev/DEVICE:BAUD, got 'bogus'");
  EXPECT_EQ(error("tcp://host"), "--modbus: expected tcp://HOST:PORT");
  EXPECT_EQ(error("tcp://127.0.0.1:x"), "--modbus: bad port in 'tcp://127.0.0.1:x'");
  EXPECT_EQ(error("tcp://127.0.0.1:65536"),
            "--modbus: port 65536 out of range (0 to 65535) in 'tcp://127.0.0.1:65536'");
  // Whole numbers only: a prefix is not a port (std::stoi read "15x" as 15, "1502.9" as 1502).
  EXPECT_EQ(error("tcp://127.0.0.1:15x"), "--modbus: bad port in 'tcp://127.0.0.1:15x'");
  EXPECT_EQ(error("tcp://127.0.0.1:1502.9"), "--modbus: bad port in 'tcp://127.0.0.1:1502.9'");
  EXPECT_EQ(error("tcp://127.0.0.1: 1502"), "--modbus: bad port in 'tcp://127.0.0.1: 1502'");
  EXPECT_EQ(error("tcp://127.0.0.1:+1502"), "--modbus: bad port in 'tcp://127.0.0.1:+1502'");
  EXPECT_EQ(error("tcp://127.0.0.1:"), "--modbus: bad port in 'tcp://127.0.0.1:'");
  EXPECT_EQ(error("tcp://127.0.0.1:99999999999999999999"),
            "--modbus: bad port in 'tcp://127.0.0.1:99999999999999999999'");
  EXPECT_EQ(error("rtu:/dev/null:9600x"), "--modbus: bad baud rate in 'rtu:/dev/null:9600x'");
  EXPECT_EQ(error("rtu:/dev/null:-9600"), "--modbus: bad baud rate in 'rtu:/dev/null:-9600'");
  EXPECT_EQ(error("rtu:/dev/null:abc"), "--modbus: bad baud rate in 'rtu:/dev/null:abc'");
  EXPECT_EQ(error("rtu:/dev/null:0"), "--modbus: bad baud rate in 'rtu:/dev/null:0'");
}

TEST(EmuOptions, ModbusTcpOptions) {
  const ModbusTcpOptions tcp = modbus_tcp_options(parse_with_config(
      {"--modbus-idle-timeout-ms", "0", "--modbus-frame-timeout-ms", "86400000", "--modbus-evict-idle-ms", "250"}));
  EXPECT_EQ(tcp.idle_timeout_ms, 0);
  EXPECT_EQ(tcp.frame_timeout_ms, 86400000);
  EXPECT_EQ(tcp.evict_idle_ms, 250);
  EXPECT_EQ(tcp.max_clients, 16);
}

TEST(EmuOptions, CanTransportConfigInSiUnits) {
  const CanTransportConfig can = can_transport_config(
      parse_with_config({"--node", "127", "--telemetry-hz", "250", "--heartbeat-ms", "500"}));
  EXPECT_EQ(can.node, 127);
  EXPECT_EQ(can.telemetry_hz, 250.0);
  EXPECT_DOUBLE_EQ(can.heartbeat_s, 0.5);
  const CanTransportConfig defaults = can_transport_config(parse_with_config({}));
  EXPECT_EQ(defaults.node, 1);
  EXPECT_EQ(defaults.telemetry_hz, 100.0);
  EXPECT_DOUBLE_EQ(defaults.heartbeat_s, 1.0);
}

TEST(EmuOptions, GpioConfigInSiUnits) {
  const GpioConfig gpio = gpio_config(
      parse_with_config({"--gpio", "gpiochip1:enable=3,fault=4,a=5,b=6", "--encoder-resolution-um", "2.5",
                         "--encoder-max-rate-hz", "5000"}));
  EXPECT_EQ(gpio.chip, "gpiochip1");
  EXPECT_EQ(gpio.enable, 3);
  EXPECT_EQ(gpio.fault, 4);
  EXPECT_EQ(gpio.encoder_a, 5);
  EXPECT_EQ(gpio.encoder_b, 6);
  EXPECT_DOUBLE_EQ(gpio.encoder_resolution_m, 2.5e-6);
  EXPECT_EQ(gpio.max_edge_rate_hz, 5000.0);
  const GpioConfig defaults = gpio_config(parse_with_config({"--gpio", "gpiochip0:enable=3,fault=4"}));
  EXPECT_EQ(defaults.encoder_a, -1);
  EXPECT_DOUBLE_EQ(defaults.encoder_resolution_m, 10e-6);
  EXPECT_EQ(defaults.max_edge_rate_hz, 20000.0);
}

TEST(EmuOptions, BadGpioSpecRefused) {
  const auto error = [](const char* spec) { return refusal(&EmuOptions::gpio_spec, spec, gpio_config); };
  EXPECT_EQ(error("bogus"), "--gpio: expected CHIP:enable=N,fault=M[,a=K,b=L], got 'bogus'");
  EXPECT_EQ(error("gpiochip0:enable"), "--gpio: expected NAME=OFFSET in 'enable'");
  EXPECT_EQ(error("gpiochip0:enable=x"), "--gpio: bad line offset in 'enable=x'");
  EXPECT_EQ(error("gpiochip0:fault=-1"), "--gpio: bad line offset in 'fault=-1'");
  EXPECT_EQ(error("gpiochip0:enable=3x"), "--gpio: bad line offset in 'enable=3x'");
  EXPECT_EQ(error("gpiochip0:enable=3.5"), "--gpio: bad line offset in 'enable=3.5'");
  EXPECT_EQ(error("gpiochip0:enable= 3"), "--gpio: bad line offset in 'enable= 3'");
  EXPECT_EQ(error("gpiochip0:reset=1"), "--gpio: unknown GPIO line 'reset' (enable, fault, a, b)");
  EXPECT_EQ(error("gpiochip0:enable=1,a=2"), "--gpio: the encoder needs both a= and b=");
}

TEST(EmuOptions, LoopConfig) {
  const LoopConfig loop = loop_config(
      parse_with_config({"--tick-hz", "2000", "--duration-s", "2.5", "--speedup", "4", "--spin-us", "50", "--rt"}));
  EXPECT_EQ(loop.speedup, 4.0);
  EXPECT_TRUE(loop.realtime);
  EXPECT_DOUBLE_EQ(loop.spin_s, 50e-6);
  EXPECT_EQ(loop.max_ticks, 5000u);         // 2.5 emulated s at 2 kHz
  EXPECT_EQ(loop.stats_every_ticks, 200u);  // ~10 times per emulated second
  const LoopConfig defaults = loop_config(parse_with_config({}));
  EXPECT_EQ(defaults.speedup, 1.0);
  EXPECT_FALSE(defaults.realtime);
  EXPECT_EQ(defaults.spin_s, 0.0);
  EXPECT_EQ(defaults.max_ticks, 0u);  // until SIGINT/SIGTERM
  EXPECT_EQ(defaults.stats_every_ticks, 1000u);
  EXPECT_EQ(defaults.priority, 80);
  // Rounded to whole ticks; the publication interval is at least one tick.
  EXPECT_EQ(loop_config(parse_with_config({"--tick-hz", "100", "--duration-s", "0.016"})).max_ticks, 2u);
  EXPECT_EQ(loop_config(parse_with_config({"--tick-hz", "100"})).stats_every_ticks, 10u);
  EXPECT_EQ(loop_config(with([](EmuOptions& o) { o.tick_hz = 5.0; })).stats_every_ticks, 1u);
}

}  // namespace
}  // namespace swum::emu

namespace swum::emu {
namespace {

// Issue 13: the lockstep, scenario and record/replay options and what they refuse.
TEST(EmuOptions, LockstepScenarioAndTraceOptions) {
  const EmuOptions o = parse_with_config({"--clock", "external", "--can", "vcan0", "--sync-ticks", "20", "--scenario",
                                          kConfig, "--inject", "jam@1", "--inject", "clear@2:fault=jam", "--record",
                                          "/tmp/t.csv"});
  EXPECT_TRUE(o.external_clock);
  EXPECT_EQ(o.sync_ticks, 20);
  EXPECT_EQ(o.scenario_path, kConfig);
  EXPECT_EQ(o.injections, (std::vector<std::string>{"jam@1", "clear@2:fault=jam"}));
  EXPECT_EQ(o.record_path, "/tmp/t.csv");
  EXPECT_EQ(lockstep_config(parse_with_config({"--clock", "external", "--duration-s", "0.5"})).max_ticks, 5000U);
  EXPECT_FALSE(parse_with_config({}).external_clock);
}

TEST(EmuOptions, LockstepRefusalsNameTheOption) {
  EXPECT_EQ(parse_error({"--clock", "external", "--speedup", "2"}),
            "--speedup paces wall time; with --clock external time advances only when the controller steps it");
  EXPECT_EQ(parse_error({"--clock", "external", "--spin-us", "5"}),
            "--spin-us paces wall time; with --clock external time advances only when the controller steps it");
  EXPECT_EQ(parse_error({"--sync-ticks", "5"}),
            "--sync-ticks: only with --clock external and --can (ticks per CAN SYNC)");
  EXPECT_EQ(parse_error({"--replay", kConfig, "--record", "/tmp/x.csv"}),
            "--replay and --record: a replay records nothing (it compares with its trace)");
  for (const char* option : {"--modbus", "--can", "--clock", "--duration-s"}) {
    const std::string value = std::string(option) == "--clock" ? "external" : "1";
    EXPECT_EQ(parse_error({"--replay", kConfig, option, value}),
              std::string(option) + " has no effect with --replay (a replay opens no interface and runs on no clock)");
  }
  EXPECT_EQ(cli_exit({"--config", kConfig, "--clock", "sometimes"}).exit_code(), 105);  // CLI11 ValidationError
}

// --http: off by default; HOST:PORT parsed with the --modbus grammar; the token from the option
// or a file's first line; the --http-* options only with --http.
TEST(EmuOptions, HttpIsOffByDefault) { EXPECT_FALSE(http_config(parse_with_config({})).has_value()); }

TEST(EmuOptions, HttpTakesHostAndPortAndItsLimits) {
  const EmuOptions o = parse_with_config({"--http", "127.0.0.1:0", "--http-stream-hz", "50", "--http-stream-clients",
                                          "2", "--http-max-body-bytes", "1000", "--http-token", "abc-123"});
  const std::optional<HttpConfig> http = http_config(o);
  ASSERT_TRUE(http.has_value());
  EXPECT_EQ(http->host, "127.0.0.1");
  EXPECT_EQ(http->port, 0);
  EXPECT_EQ(http->stream_default_hz, 50.0);
  EXPECT_EQ(http->max_stream_clients, 2);
  EXPECT_EQ(http->max_body_bytes, 1000U);
  EXPECT_EQ(http->token, "abc-123");
  EXPECT_FALSE(http->trace_recording);
  EXPECT_FALSE(http->recording_directory.empty());
}

TEST(EmuOptions, HttpRefusesWhatIsNotHostAndPort) {
  for (const char* bad : {"nonsense", "127.0.0.1", "127.0.0.1:99999", "http://127.0.0.1:80", "127.0.0.1:-1", ":0"}) {
    const std::string e = option_error([&] { http_config(parse_with_config({"--http", bad})); });
    EXPECT_NE(e.find("--http '"), std::string::npos) << bad << ": " << e;
  }
}

TEST(EmuOptions, HttpOptionsNeedHttp) {
  EXPECT_EQ(parse_error({"--http-token", "x"}), "--http-token: only with --http");
  EXPECT_EQ(parse_error({"--http-stream-clients", "2"}), "--http-stream-clients: only with --http");
  EXPECT_EQ(parse_error({"--http", "127.0.0.1:0", "--http-token", ""}), "--http-token: empty");
  EXPECT_EQ(parse_error({"--http", "", "--http-token", "x"}),
            "--http: empty (expected HOST:PORT, e.g. 127.0.0.1:8080)");
}

TEST(EmuOptions, HttpTokenComesFromTheFirstLineOfAFile) {
  const std::string path = testing::TempDir() + "swum_emu_token.txt";
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("from-the-file\r\nsecond line\n", f);
    std::fclose(f);
  }
  const auto http = http_config(parse_with_config({"--http", "127.0.0.1:0", "--http-token-file", path}));
  ASSERT_TRUE(http.has_value());
  EXPECT_EQ(http->token, "from-the-file");
  EXPECT_EQ(parse_error({"--http", "127.0.0.1:0", "--http-token-file", path, "--http-token", "x"}),
            "--http-token and --http-token-file: give one");
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("\n", f);
    std::fclose(f);
  }
  const std::string e = option_error([&] {
    http_config(parse_with_config({"--http", "127.0.0.1:0", "--http-token-file", path}));
  });
  EXPECT_NE(e.find("the first line is empty"), std::string::npos) << e;
  std::remove(path.c_str());
}

TEST(EmuOptions, HttpTokenWithASpaceCannotBeSent) {
  const std::string e = option_error([&] {
    http_config(parse_with_config({"--http", "127.0.0.1:0", "--http-token", "a b"}));
  });
  EXPECT_NE(e.find("spaces and control characters"), std::string::npos) << e;
}

TEST(EmuOptions, HttpWithRecordRefusesRunTimeFaults) {
  const auto http = http_config(parse_with_config({"--http", "127.0.0.1:0", "--record", "/tmp/x.csv"}));
  ASSERT_TRUE(http.has_value());
  EXPECT_TRUE(http->trace_recording);
}

TEST(EmuOptions, HttpHasNoEffectWithReplay) {
  const std::string e = parse_error({"--replay", kConfig, "--http", "127.0.0.1:0"});
  EXPECT_NE(e.find("--http has no effect with --replay"), std::string::npos) << e;
}

}  // namespace
}  // namespace swum::emu

namespace swum::emu {
namespace {

// --can-profile: swum by default, cia402 on request, nothing else; only with --can; cia402's
// heartbeat is 0x1017 (UNSIGNED16 ms) and --heartbeat-ms sets it only when given.
TEST(EmuOptions, CanProfileIsSwumOrCia402AndOnlyWithCan) {
  EXPECT_EQ(parse_with_config({"--can", "vcan0"}).can_profile, "swum");
  const EmuOptions o = parse_with_config({"--can", "vcan0", "--can-profile", "cia402"});
  EXPECT_EQ(o.can_profile, "cia402");
  EXPECT_FALSE(o.heartbeat_given);
  EXPECT_EQ(canopen_profile_config(o, AmplifierLimits{}).heartbeat_ms, -1);  // the EDS default
  const EmuOptions h = parse_with_config({"--can", "vcan0", "--can-profile", "cia402", "--heartbeat-ms", "250"});
  EXPECT_EQ(canopen_profile_config(h, AmplifierLimits{}).heartbeat_ms, 250);
  EXPECT_NE(cli_exit({"--config", kConfig, "--can", "vcan0", "--can-profile", "canopen"}).exit_code(), 0);
  EXPECT_EQ(parse_error({"--can-profile", "cia402"}), "--can-profile: only with --can");
  EXPECT_EQ(parse_error({"--can", "vcan0", "--can-profile", "cia402", "--heartbeat-ms", "70000"}),
            "--heartbeat-ms: at most 65535 with --can-profile cia402 (0x1017 is UNSIGNED16 ms)");
}

}  // namespace
}  // namespace swum::emu
