// CommandLine over CLI11 (see command_line.hpp): the one translation unit that compiles CLI11.
#include "common/command_line.hpp"

#include <algorithm>
#include <iostream>

#include <CLI/CLI.hpp>

namespace igi::programs {

CommandLineOption& CommandLineOption::choices(std::initializer_list<std::string> values) {
  option_->check(CLI::IsMember(std::vector(values)));
  return *this;
}

CommandLineOption& CommandLineOption::choices(std::initializer_list<int> values) {
  option_->check(CLI::IsMember(std::vector(values)));
  return *this;
}

CommandLineOption& CommandLineOption::range(int low, int high) {
  option_->check(CLI::Range(low, high));
  return *this;
}

CommandLineOption& CommandLineOption::range(double low, double high) {
  option_->check(CLI::Range(low, high));
  return *this;
}

CommandLineOption& CommandLineOption::show_default() {
  option_->capture_default_str();
  return *this;
}

CommandLineOption& CommandLineOption::required() {
  option_->required();
  return *this;
}

CommandLine::CommandLine(const std::string& program, const std::string& description)
    : program_(program), app_(std::make_unique<CLI::App>(program + ": " + description)) {}

CommandLine::~CommandLine() = default;

CommandLineOption CommandLine::add(const std::string& names, std::string& value, const std::string& help) {
  return CommandLineOption(app_->add_option(names, value, help));
}

CommandLineOption CommandLine::add(const std::string& names, int& value, const std::string& help) {
  return CommandLineOption(app_->add_option(names, value, help));
}

CommandLineOption CommandLine::add(const std::string& names, std::uint32_t& value, const std::string& help) {
  return CommandLineOption(app_->add_option(names, value, help));
}

CommandLineOption CommandLine::add(const std::string& names, float& value, const std::string& help) {
  return CommandLineOption(app_->add_option(names, value, help));
}

CommandLineOption CommandLine::add(const std::string& names, double& value, const std::string& help) {
  return CommandLineOption(app_->add_option(names, value, help));
}

CommandLineOption CommandLine::add(const std::string& names, std::optional<int>& value, const std::string& help) {
  return CommandLineOption(app_->add_option_function<int>(names, [&value](const int& given) { value = given; }, help));
}

void CommandLine::flag(const std::string& names, bool& value, const std::string& help) {
  app_->add_flag(names, value, help);
}

std::optional<int> CommandLine::parse(int argc, char** argv, bool speak) {
  try {
    app_->parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::CallForHelp& help) {
    if (speak) app_->exit(help);
    return 0;
  } catch (const CLI::ParseError& error) {
    if (speak) std::cerr << program_ << ": " << error.what() << "\n";
    return 2;
  }
}

void CommandLine::parse_arguments(const std::vector<std::string>& arguments) {
  std::vector<std::string> reversed(arguments.rbegin(), arguments.rend());  // CLI11 takes a vector last argument first
  try {
    app_->parse(reversed);
  } catch (const CLI::ParseError& error) {
    throw UsageError(error.what());
  }
}

std::vector<CommandLine::OptionName> CommandLine::option_names() const {
  std::vector<OptionName> names;
  for (const CLI::Option* option : app_->get_options()) {
    if (option->get_lnames().empty() || option == app_->get_help_ptr()) continue;
    names.push_back({"--" + option->get_lnames().front(), option->get_expected_max() == 0});
  }
  return names;
}

}  // namespace igi::programs
