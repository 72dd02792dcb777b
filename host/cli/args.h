// Command-line tokens: `--name value`, `--name=value`, bare flags and positional arguments.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "scene/environment.h"

namespace pmcr::cli {

class Args {
public:
    Args(int argc, char** argv, int first);
    explicit Args(std::vector<std::string> tokens) : m_tokens(std::move(tokens)) {}

    bool done() const { return m_pos >= m_tokens.size(); }
    const std::string& peek() const { return m_tokens[m_pos]; }
    // The next token; an option's inline value (`--x=3`) is split off and returned by value().
    std::string next();
    // The value of the option just read (inline or the following token); error if missing.
    std::string value(const std::string& option);

private:
    std::vector<std::string> m_tokens;
    size_t m_pos = 0;
    std::optional<std::string> m_inlineValue;
};

// Strict conversions that name the option in their error message.
uint32_t parseUint(const std::string& option, const std::string& text, uint32_t min, uint32_t max);
int parseInt(const std::string& option, const std::string& text, int min, int max);
double parseDouble(const std::string& option, const std::string& text, double min, double max);

// Reads option `a` into `env` when it is --env, --env-rotate or --env-scale (render and bench
// share them); false for any other option.
bool parseEnvironmentOption(const std::string& a, Args& args, EnvironmentSpec& env);
// Throws pmcr::Error for --env-rotate or --env-scale without --env.
void checkEnvironmentOptions(const EnvironmentSpec& env);

// The help lines of those options.
extern const char* const kEnvironmentHelp;

}  // namespace pmcr::cli
