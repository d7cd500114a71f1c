#pragma once
// The command line of igi's programs: CLI11 behind a small interface. CLI11 is header-only and
// costs some 20 CPU-seconds in every program that uses it directly (at -O3); behind this class it
// is compiled once, in command_line.cpp (the CMake target igi_command_line).

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace igi::programs {

/// A usage error: exit code 2 with a one-line message.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One option of a CommandLine, to attach checks to.
class CommandLineOption {
 public:
  /// The value must be one of `values`.
  CommandLineOption& choices(std::initializer_list<std::string> values);
  /// The value must be one of `values`.
  CommandLineOption& choices(std::initializer_list<int> values);
  /// The value must lie in [low, high].
  CommandLineOption& range(int low, int high);
  /// The value must lie in [low, high].
  CommandLineOption& range(double low, double high);
  /// --help shows the value the variable had when the option was added.
  CommandLineOption& show_default();
  /// The option must be given.
  CommandLineOption& required();

 private:
  friend class CommandLine;
  explicit CommandLineOption(CLI::Option* option) noexcept : option_(option) {}
  CLI::Option* option_;  ///< Owned by the CommandLine.
};

/// A program's command line: options bound to variables, then parsed.
class CommandLine {
 public:
  /// An empty command line of `program`; "program: description" heads --help.
  CommandLine(const std::string& program, const std::string& description);
  ~CommandLine();
  CommandLine(const CommandLine&) = delete;             ///< Options point into the variables and the parser.
  CommandLine& operator=(const CommandLine&) = delete;  ///< Options point into the variables and the parser.

  /// An option such as "-o,--output" (a positional argument when `names` has no leading dash) that sets `value`.
  CommandLineOption add(const std::string& names, std::string& value, const std::string& help);
  /// An option such as "-o,--output" (a positional argument when `names` has no leading dash) that sets `value`.
  CommandLineOption add(const std::string& names, int& value, const std::string& help);
  /// An option such as "-o,--output" (a positional argument when `names` has no leading dash) that sets `value`.
  CommandLineOption add(const std::string& names, std::uint32_t& value, const std::string& help);
  /// An option such as "-o,--output" (a positional argument when `names` has no leading dash) that sets `value`.
  CommandLineOption add(const std::string& names, float& value, const std::string& help);
  /// An option such as "-o,--output" (a positional argument when `names` has no leading dash) that sets `value`.
  CommandLineOption add(const std::string& names, double& value, const std::string& help);
  /// An option such as "--temporal" that sets `value` when given and leaves it empty otherwise, for
  /// a default the program resolves after parsing (from other options).
  CommandLineOption add(const std::string& names, std::optional<int>& value, const std::string& help);
  /// A flag that sets `value` to true when given.
  void flag(const std::string& names, bool& value, const std::string& help);

  /// Parses the arguments into the variables. Returns the exit code when the program should stop
  /// now: 0 after printing --help to stdout, 2 after printing "program: problem" to stderr for a
  /// bad command line; nothing when it should go on. With `speak` false it prints neither (for
  /// all but one of several processes parsing the same command line).
  std::optional<int> parse(int argc, char** argv, bool speak = true);
  /// Parses `arguments` (without a program name) into the variables, for callers that are no
  /// program's main (the Python module); throws UsageError with the parser's message for a bad one.
  void parse_arguments(const std::vector<std::string>& arguments);

  /// One option's long name ("--vpls") and whether it is a flag, taking no value.
  struct OptionName {
    std::string name;  ///< The long name with its dashes.
    bool flag;         ///< True for a flag.
  };
  /// The options that have a long name, in the order they were added (--help left out).
  std::vector<OptionName> option_names() const;

 private:
  std::string program_;            ///< Name in messages.
  std::unique_ptr<CLI::App> app_;  ///< The CLI11 parser.
};

}  // namespace igi::programs
