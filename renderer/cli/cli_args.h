// A small table-driven option parser: long and short names, fixed argument counts, generated help,
// and one-line errors for bad flags.
#pragma once

#include <functional>
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
    ArgParser(std::string command, std::string synopsis)
        : command_(std::move(command)), synopsis_(std::move(synopsis)) {}

    using Handler = std::function<void(const std::vector<std::string>&)>;
    // shortName may be empty; metavar names the arguments in help ("" for a switch).
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
    // Returns positional arguments. Throws UsageError; sets helpRequested() on -h/--help.
    std::vector<std::string> parse(const std::vector<std::string>& args);
    bool helpRequested() const { return help_; }
    std::string helpText() const;

    // "--NAME takes CHOICES, got 'VALUE'"
    static std::string badChoice(const std::string& longName, const std::string& choices,
                                 const std::string& value);
    static int toInt(const std::string& option, const std::string& text, int lo, int hi);
    static double toDouble(const std::string& option, const std::string& text);

  private:
    struct Option {
        std::string longName, shortName, metavar, help;
        int nargs;
        Handler handler;
    };
    std::string command_, synopsis_;
    std::vector<Option> options_;
    bool help_ = false;
};

}  // namespace kiln
