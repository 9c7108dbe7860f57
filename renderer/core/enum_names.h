// One name table per enum: the command line parses with it, metadata and help print with it, so an
// option's spelling lives in one place. Specialise EnumNames<E> beside the enum:
//   template <> struct EnumNames<Roulette> {
//       static constexpr std::pair<Roulette, const char*> table[] = {{Roulette::Off, "off"}, ...};
//   };
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace kiln {

template <class E>
struct EnumNames;

template <class E>
const char* toString(E value) {
    for (const auto& [v, name] : EnumNames<E>::table)
        if (v == value) return name;
    return "?";
}

template <class E>
std::optional<E> parseEnum(std::string_view text) {
    for (const auto& [v, name] : EnumNames<E>::table)
        if (text == name) return v;
    return std::nullopt;
}

// "a|b|c", for help texts and error messages.
template <class E>
std::string enumChoices() {
    std::string out;
    for (const auto& [v, name] : EnumNames<E>::table) {
        if (!out.empty()) out += '|';
        out += name;
    }
    return out;
}

}  // namespace kiln
