// Validation of COLLADA geometry before Assimp reads it: Assimp 5.2 trusts array counts, accessor
// ranges and index lists, and dereferences null or allocates without bound when they are garbled.
#include <charconv>
#include <climits>
#include <cstdlib>
#include <map>
#include <string_view>

#include "scene/cgl_extras.h"
#include "scene/scene_error.h"

namespace kiln {
namespace {

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// Calls fn(token) for every whitespace-separated token of text.
template <typename Fn>
void forEachToken(const char* text, Fn&& fn) {
    const char* p = text;
    while (*p) {
        while (isBlank(*p)) ++p;
        const char* start = p;
        while (*p && !isBlank(*p)) ++p;
        if (p > start) fn(std::string_view(start, size_t(p - start)));
    }
}

// A non-negative integer that fits an int (what Assimp stores counts and indices in), or -1.
long long strictCount(std::string_view s) {
    long long v = -1;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || v < 0 || v > INT_MAX) return -1;
    return v;
}

class Checker {
  public:
    explicit Checker(const std::string& file) : file_(file) {}

    void check(pugi::xml_node node) {
        std::string name = node.name();
        for (pugi::xml_attribute a : node.attributes()) {
            std::string an = a.name();
            if ((an == "count" || an == "stride" || an == "offset" || an == "set") &&
                strictCount(a.as_string()) < 0)
                fail(node, an + "=\"" + a.as_string() + "\" is not a non-negative integer");
        }
        if (name == "float_array" || name == "int_array") checkArray(node, name == "int_array");
        if (name == "p" || name == "vcount" || name == "v" || name == "h")
            forEachToken(node.child_value(), [&](std::string_view t) {
                if (strictCount(t) < 0)
                    fail(node, "index '" + std::string(t) + "' is not a non-negative integer");
            });
        for (pugi::xml_node child : node.children())
            if (child.type() == pugi::node_element) check(child);
    }

    // Accessors last: every array's length is known by then.
    void checkAccessors(pugi::xml_node node) {
        if (std::string(node.name()) == "accessor") {
            std::string src = node.attribute("source").as_string();
            if (!src.empty() && src[0] == '#') src.erase(0, 1);
            auto it = arrayLength_.find(src);
            if (it == arrayLength_.end()) fail(node, "source '" + src + "' names no array");
            long long count = node.attribute("count").as_llong(0);
            long long stride = node.attribute("stride").as_llong(1);
            long long offset = node.attribute("offset").as_llong(0);
            if (count > 0 && offset + count * stride > it->second)
                fail(node, "reads " + std::to_string(offset + count * stride) + " values of '" +
                               src + "', which has " + std::to_string(it->second));
        }
        for (pugi::xml_node child : node.children()) checkAccessors(child);
    }

  private:
    void checkArray(pugi::xml_node node, bool integers) {
        long long declared = strictCount(node.attribute("count").as_string());
        if (declared < 0) fail(node, "needs a count attribute that is a non-negative integer");
        long long found = 0;
        forEachToken(node.child_value(), [&](std::string_view t) {
            std::string token(t);
            char* end = nullptr;
            if (integers)
                (void)std::strtoll(token.c_str(), &end, 10);
            else
                (void)std::strtod(token.c_str(), &end);
            if (end != token.c_str() + token.size()) fail(node, "garbled number '" + token + "'");
            ++found;
        });
        if (found != declared)
            fail(node, "count=\"" + std::to_string(declared) + "\" but it holds " +
                           std::to_string(found) + " numbers");
        if (const char* id = node.attribute("id").as_string(); *id) arrayLength_[id] = found;
    }

    [[noreturn]] void fail(pugi::xml_node node, const std::string& what) const {
        std::string id = node.attribute("id").as_string();
        throw SceneError(file_, "<" + std::string(node.name()) +
                                    (id.empty() ? "" : " id=\"" + id + "\"") + "> " + what);
    }

    const std::string& file_;
    std::map<std::string, long long> arrayLength_;
};

}  // namespace

void checkColladaGeometry(const std::string& path, pugi::xml_node collada) {
    Checker checker(path);
    for (pugi::xml_node lib : collada.children("library_geometries")) checker.check(lib);
    for (pugi::xml_node lib : collada.children("library_geometries")) checker.checkAccessors(lib);
}

}  // namespace kiln
