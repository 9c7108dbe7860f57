// The commands' option declarations, a thin adapter over CLI11's CLI::App: long and short names,
// fixed argument counts, groups in the generated help, and one-line errors for bad flags. CLI11
// gives the GNU forms: -s4, -s 4, --spp=4, --spp 4, bundled switches (-qH) and -- (what follows
// is a file name, even one starting with '-').
#pragma once

#include <concepts>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/core/enum_names.h"

namespace kiln {

class UsageError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

class ArgParser {
  public:
    ArgParser(std::string command, std::string synopsis);
    ~ArgParser();
    ArgParser(ArgParser&&) noexcept;
    ArgParser& operator=(ArgParser&&) noexcept;

    // The help section the following declarations are listed under ("Options" until set);
    // returns the one before. OptionGroup sets it for a scope.
    std::string group(const std::string& name);

    using Handler = std::function<void(const std::vector<std::string>&)>;
    // shortName may be empty; metavar names the arguments in help ("" for a switch). The handler
    // runs when the option is met, in command-line order (a later -o overrides an earlier one).
    void option(const std::string& longName, const std::string& shortName, int nargs,
                const std::string& metavar, const std::string& help, Handler handler);
    void flag(const std::string& longName, const std::string& shortName, const std::string& help,
              bool& target);
    void intOption(const std::string& longName, const std::string& shortName,
                   const std::string& help, int& target, int minValue, int maxValue);
    // An option whose one argument is a name from the enum's table (renderer/core/enum_names.h).
    template <class E>
    void enumOption(const std::string& longName, const std::string& help, E& target) {
        option(longName, "", 1, enumChoices<E>(), help, [&target, longName](const auto& v) {
            std::optional<E> value = parseEnum<E>(v[0]);
            if (!value) throw UsageError(badChoice(longName, enumChoices<E>(), v[0]));
            target = *value;
        });
    }
    // The same, handing the value to apply(E) (for a choice that sets more than one field).
    template <class E, class Apply>
    requires std::invocable<Apply, E>
    void enumOption(const std::string& longName, const std::string& help, Apply apply) {
        option(longName, "", 1, enumChoices<E>(), help, [apply, longName](const auto& v) {
            std::optional<E> value = parseEnum<E>(v[0]);
            if (!value) throw UsageError(badChoice(longName, enumChoices<E>(), v[0]));
            apply(*value);
        });
    }
    // Every option declared so far, in order (the Python module maps its keywords onto them).
    struct Declared {
        std::string longName, shortName, group, metavar, help;
        int nargs;  // 0: a switch
    };
    const std::vector<Declared>& declared() const;
    // Returns positional arguments. Throws UsageError; sets helpRequested() on -h/--help.
    std::vector<std::string> parse(const std::vector<std::string>& args);
    bool helpRequested() const;
    std::string helpText();

    // "--NAME takes CHOICES, got 'VALUE'"
    static std::string badChoice(const std::string& longName, const std::string& choices,
                                 const std::string& value);
    static int toInt(const std::string& option, const std::string& text, int lo, int hi);
    static double toDouble(const std::string& option, const std::string& text);

  private:
    void declareCommon();  // --log-level and -h/--help, last in the help
    struct Impl;  // CLI::App and what its callbacks write; on the heap so a parser can move
    std::unique_ptr<Impl> impl_;
};

// Declarations made while it lives are listed under NAME in --help; the group before comes back
// at the end of the scope, so shared declarations do not regroup the caller's own.
class OptionGroup {
  public:
    OptionGroup(ArgParser& parser, const std::string& name)
        : parser_(parser), previous_(parser.group(name)) {}
    ~OptionGroup() { parser_.group(previous_); }
    OptionGroup(const OptionGroup&) = delete;
    OptionGroup& operator=(const OptionGroup&) = delete;

  private:
    ArgParser& parser_;
    std::string previous_;
};

}  // namespace kiln
