#include "renderer/cli/cli_args.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <utility>

#include "renderer/cli/did_you_mean.h"
#include "renderer/core/log.h"

namespace kiln {

namespace {

constexpr size_t kHelpColumn = 32;  // where the descriptions start

// kiln's help layout: "usage: kiln COMMAND SYNOPSIS", then each group as "Name:" with
// "  -s, --spp N    description" rows ("      --tile N" when there is no short name).
class HelpFormatter : public CLI::Formatter {
  public:
    explicit HelpFormatter(std::string usage) : usage_(std::move(usage)) {
        column_width(kHelpColumn);
    }
    std::string make_usage(const CLI::App*, std::string) const override { return usage_ + "\n\n"; }
    // CLI11 puts a blank line between groups already.
    std::string make_group(std::string group, bool positional,
                           std::vector<const CLI::Option*> opts) const override {
        std::string text = group + ":\n";
        for (const CLI::Option* opt : opts) text += make_option(opt, positional);
        return text;
    }
    std::string make_option_name(const CLI::Option* opt, bool) const override {
        std::string names;
        for (const std::string& s : opt->get_snames()) names += "-" + s + ", ";
        if (names.empty()) names = "    ";
        for (const std::string& l : opt->get_lnames()) names += "--" + l;
        return names;
    }
    std::string make_option_opts(const CLI::Option* opt) const override {
        return opt->get_type_name().empty() ? "" : " " + opt->get_type_name();
    }

  private:
    std::string usage_;
};

std::string cliNames(const std::string& longName, const std::string& shortName) {
    return (shortName.empty() ? "" : "-" + shortName + ",") + "--" + longName;
}

}  // namespace

struct ArgParser::Impl {
    std::string command;
    CLI::App app;
    std::string group = "Options";
    std::vector<std::string> positional;
    std::vector<Declared> declared;
    bool help = false;
    bool commonDeclared = false;

    Impl(std::string commandName, const std::string& synopsis)
        : command(std::move(commandName)), app("", "kiln " + command) {
        app.set_help_flag();  // -h/--help is declared last, as a plain switch (declareCommon)
        app.formatter(std::make_shared<HelpFormatter>("usage: kiln " + command + " " + synopsis));
        app.add_option("positional", positional)->group("");  // hidden: the synopsis names them
    }
    std::string usageHint() const { return "(see 'kiln " + command + " --help')"; }
    // The declared option nearest to an unknown one ("--sp" -> "--spp").
    std::string suggestion(const std::string& typed) const {
        std::vector<std::string> names{"--help", "--log-level"};
        for (const Declared& d : declared) names.push_back("--" + d.longName);
        return didYouMean(typed.substr(0, typed.find('=')), names);
    }
    // One line naming the flag, whatever CLI11 found wrong.
    UsageError translate(const CLI::ParseError& e) const {
        if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
            std::vector<std::string> extra = app.remaining();
            std::string first = extra.empty() ? "" : extra.front();
            return UsageError(
                fmt::format("unknown option '{}'{} {}", first, suggestion(first), usageHint()));
        }
        std::string text = e.what();
        std::replace(text.begin(), text.end(), '\n', ' ');
        return UsageError(fmt::format("{} {}", text, usageHint()));
    }
};

ArgParser::ArgParser(std::string command, std::string synopsis)
    : impl_(std::make_unique<Impl>(std::move(command), synopsis)) {}
ArgParser::~ArgParser() = default;
ArgParser::ArgParser(ArgParser&&) noexcept = default;
ArgParser& ArgParser::operator=(ArgParser&&) noexcept = default;

// Declared at the end, so the command's own groups come first in the help.
void ArgParser::declareCommon() {
    if (std::exchange(impl_->commonDeclared, true)) return;
    OptionGroup messages(*this, "Messages");
    enumOption<LogLevel>("log-level",
                         "the least important messages shown on stderr (default info; warning: "
                         "only warnings and errors)",
                         [](LogLevel level) { setLogLevel(level); });
    impl_->app.add_flag("-h,--help", impl_->help, "show this help")->group("Help");
}

std::string ArgParser::group(const std::string& name) { return std::exchange(impl_->group, name); }

void ArgParser::option(const std::string& longName, const std::string& shortName, int nargs,
                       const std::string& metavar, const std::string& help, Handler handler) {
    impl_->declared.push_back({longName, shortName, impl_->group, metavar, help, nargs});
    CLI::Option* opt = nullptr;
    std::string names = cliNames(longName, shortName);
    if (nargs == 0) {
        opt = impl_->app.add_flag_callback(
            names, [handler] { handler({}); }, help);
    } else {
        opt = impl_->app.add_option(
            names,
            [handler](const CLI::results_t& values) {
                handler(values);
                return true;
            },
            help);
        opt->type_size(nargs)->expected(1);
    }
    // Handlers run as the options are met, so the command line's order decides (as before CLI11).
    opt->type_name(metavar)->group(impl_->group)->trigger_on_parse();
    opt->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

void ArgParser::flag(const std::string& longName, const std::string& shortName,
                     const std::string& help, bool& target) {
    option(longName, shortName, 0, "", help,
           [&target](const std::vector<std::string>&) { target = true; });
}

void ArgParser::intOption(const std::string& longName, const std::string& shortName,
                          const std::string& help, int& target, int minValue, int maxValue) {
    std::string name = "--" + longName;
    option(longName, shortName, 1, "N", help,
           [&target, name, minValue, maxValue](const std::vector<std::string>& v) {
               target = toInt(name, v[0], minValue, maxValue);
           });
}

int ArgParser::toInt(const std::string& option, const std::string& text, int lo, int hi) {
    errno = 0;
    char* end = nullptr;
    long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end || errno)
        throw UsageError("option " + option + " needs an integer, got '" + text + "'");
    if (v < lo || v > hi)
        throw UsageError("option " + option + " must be between " + std::to_string(lo) + " and " +
                         std::to_string(hi) + ", got " + text);
    return int(v);
}

double ArgParser::toDouble(const std::string& option, const std::string& text) {
    char* end = nullptr;
    double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end || !std::isfinite(v))
        throw UsageError("option " + option + " needs a number, got '" + text + "'");
    return v;
}

std::vector<std::string> ArgParser::parse(const std::vector<std::string>& args) {
    declareCommon();
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 pops from the back
    try {
        impl_->app.parse(reversed);
    } catch (const CLI::ParseError& e) {
        throw impl_->translate(e);
    }
    return impl_->positional;
}

bool ArgParser::helpRequested() const { return impl_->help; }

const std::vector<ArgParser::Declared>& ArgParser::declared() const { return impl_->declared; }

std::string ArgParser::helpText() {
    declareCommon();
    std::string text = impl_->app.help();
    while (text.size() > 1 && text.back() == '\n' && text[text.size() - 2] == '\n') text.pop_back();
    return text;
}

std::string ArgParser::badChoice(const std::string& longName, const std::string& choices,
                                 const std::string& value) {
    return fmt::format("--{} takes {}, got '{}'", longName, choices, value);
}

}  // namespace kiln
