#include "renderer/cli/cli_args.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace kiln {

void ArgParser::option(const std::string& longName, const std::string& shortName, int nargs,
                       const std::string& metavar, const std::string& help, Handler handler) {
    options_.push_back({longName, shortName, metavar, help, nargs, std::move(handler)});
}

void ArgParser::flag(const std::string& longName, const std::string& shortName,
                     const std::string& help, bool& target) {
    option(longName, shortName, 0, "", help,
           [&target](const std::vector<std::string>&) { target = true; });
}

void ArgParser::intOption(const std::string& longName, const std::string& shortName,
                          const std::string& help, int& target, int minValue, int maxValue) {
    std::string name = longName;
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
    std::vector<std::string> positional;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "-h" || a == "--help") {
            help_ = true;
            continue;
        }
        if (a.size() < 2 || a[0] != '-' || (a[1] >= '0' && a[1] <= '9')) {
            positional.push_back(a);
            continue;
        }
        std::string name = a, inlineValue;
        bool hasInline = false;
        if (a.rfind("--", 0) == 0) {
            size_t eq = a.find('=');
            if (eq != std::string::npos)
                name = a.substr(0, eq), inlineValue = a.substr(eq + 1), hasInline = true;
        }
        const Option* opt = nullptr;
        for (const Option& o : options_)
            if (name == "--" + o.longName || (!o.shortName.empty() && name == "-" + o.shortName))
                opt = &o;
        if (!opt)
            throw UsageError("unknown option '" + a + "' (see 'kiln " + command_ + " --help')");
        std::vector<std::string> values;
        if (hasInline) {
            if (opt->nargs != 1) throw UsageError("option " + name + " does not take '=value'");
            values.push_back(inlineValue);
        } else {
            for (int k = 0; k < opt->nargs; ++k) {
                if (i + 1 >= args.size())
                    throw UsageError("option " + name + " needs " + std::to_string(opt->nargs) +
                                     " value(s): " + opt->metavar);
                values.push_back(args[++i]);
            }
        }
        opt->handler(values);
    }
    return positional;
}

std::string ArgParser::helpText() const {
    std::ostringstream os;
    os << "usage: kiln " << command_ << " " << synopsis_ << "\n\noptions:\n";
    for (const Option& o : options_) {
        std::string names =
            (o.shortName.empty() ? "    " : "-" + o.shortName + ", ") + "--" + o.longName;
        if (!o.metavar.empty()) names += " " + o.metavar;
        os << "  " << names;
        if (names.size() < 30)
            os << std::string(30 - names.size(), ' ');
        else
            os << "\n  " << std::string(30, ' ');
        os << o.help << "\n";
    }
    os << "  -h, --help                    show this help\n";
    return os.str();
}

std::string ArgParser::badChoice(const std::string& longName, const std::string& choices,
                                 const std::string& value) {
    std::string message = "--";
    message.append(longName).append(" takes ").append(choices).append(", got '");
    return message.append(value).append("'");
}

}  // namespace kiln
