#include "renderer/farm/job_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

namespace kiln::farm {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// The render options one camera entry (or one keyframe of a path) stands for.
struct CameraFrame {
    std::string camera;
    int frame = 0;
    std::vector<std::string> args;
    std::vector<ArgSource> sources;  // args by the key they come from
};

struct Setting {
    std::string name;
    std::vector<std::string> args;
    std::string where;
};

// One key's options as a source of its own, appended to args.
void addSource(CameraFrame& f, const std::string& where, const std::vector<std::string>& args) {
    if (args.empty()) return;
    f.args.insert(f.args.end(), args.begin(), args.end());
    f.sources.push_back({where, args});
}

[[noreturn]] void fail(const std::string& where, const std::string& what) {
    throw FarmInputError(where + ": " + what);
}

void onlyKeys(const json& object, const std::set<std::string>& allowed, const std::string& where) {
    if (!object.is_object()) fail(where, "must be a JSON object");
    for (const auto& [key, value] : object.items())
        if (!allowed.count(key)) fail(where, "unknown key '" + key + "'");
}

std::string numberText(const json& v, const std::string& where) {
    // Unsigned as written: 18446744073709551615 read as a long long was "-1" in the message.
    if (v.is_number_unsigned()) return std::to_string(v.get<unsigned long long>());
    if (v.is_number_integer()) return std::to_string(v.get<long long>());
    if (v.is_number()) return fmt::format("{:.9g}", v.get<double>());
    if (v.is_string()) return v.get<std::string>();
    fail(where, "must be a string or a number");
}

// An option that names the render's files: the job's 'output' pattern does that for every render
// (-o 0 and -o 1 are CS184's accumulate-bounces switch, not a name).
bool namesOutput(const std::vector<std::string>& args, size_t i) {
    const std::string& a = args[i];
    if (a == "-o" || a == "--accumulate")
        return i + 1 < args.size() && args[i + 1] != "0" && args[i + 1] != "1";
    for (const char* flag : {"--output", "--file", "-f"})
        if (a == flag || a.rfind(std::string(flag) + "=", 0) == 0) return true;
    return false;
}

std::vector<std::string> argList(const json& v, const std::string& where) {
    if (!v.is_array()) fail(where, "must be an array of render options");
    std::vector<std::string> args;
    for (const json& a : v) args.push_back(numberText(a, where));
    for (size_t i = 0; i < args.size(); ++i)
        if (namesOutput(args, i))
            fail(where, "'" + args[i] +
                            "' names the output, which the job's 'output' pattern names for "
                            "every render (it was silently replaced)");
    return args;
}

void addVec3(CameraFrame& f, const json& entry, const char* key, const std::string& option,
             const std::string& where) {
    if (!entry.contains(key)) return;
    const json& v = entry[key];
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
        !v[2].is_number())
        fail(where, std::string("'") + key + "' must be three numbers");
    std::vector<std::string> args{option};
    for (const json& x : v) args.push_back(numberText(x, where));
    addSource(f, where + ": '" + key + "'", args);
}

void addViewArgs(CameraFrame& f, const json& entry, const std::string& where) {
    addVec3(f, entry, "position", "--position", where);
    addVec3(f, entry, "look_at", "--look-at", where);
    addVec3(f, entry, "up", "--up", where);
    if (entry.contains("fov")) {
        if (!entry["fov"].is_number()) fail(where, "'fov' must be a number");
        addSource(f, where + ": 'fov'", {"--fov", numberText(entry["fov"], where)});
    }
}

int intIn(const json& v, int lo, int hi, const std::string& where) {
    if (!v.is_number_integer() || v.get<long long>() < lo || v.get<long long>() > hi)
        fail(where, "must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
    return int(v.get<long long>());
}

std::vector<CameraFrame> turntableFrames(const json& c, const std::string& name,
                                         const std::string& where) {
    int n = intIn(c["turntable"], 1, 1 << 20, where + ": 'turntable'");
    int first = 0, last = n;
    if (c.contains("frames")) {
        const json& f = c["frames"];
        if (!f.is_array() || f.size() != 2) fail(where, "'frames' must be [FIRST, END)");
        first = intIn(f[0], 0, n - 1, where + ": 'frames'");
        last = intIn(f[1], first + 1, n, where + ": 'frames'");
    }
    CameraFrame base{name, 0, {}, {}};
    addViewArgs(base, c, where);
    addVec3(base, c, "axis", "--orbit-axis", where);
    addVec3(base, c, "centre", "--orbit-centre", where);
    std::vector<CameraFrame> frames;
    for (int k = first; k < last; ++k) {
        CameraFrame f = base;
        f.frame = k;
        addSource(f, where + ": 'turntable'",
                  {"--turntable", std::to_string(n), "--frame", std::to_string(k)});
        frames.push_back(f);
    }
    return frames;
}

std::vector<CameraFrame> cameraFrames(const json& c, size_t i, const std::string& file) {
    std::string where = file + ": cameras[" + std::to_string(i) + "]";
    onlyKeys(c,
             {"name", "position", "look_at", "up", "fov", "turntable", "frames", "axis", "centre",
              "path"},
             where);
    std::string name = "cam" + std::to_string(i);
    if (c.contains("name")) {
        if (!c["name"].is_string()) fail(where, "'name' must be a string");
        name = c["name"].get<std::string>();
    }
    if (c.contains("turntable")) return turntableFrames(c, name, where);
    if (!c.contains("path")) {
        CameraFrame f{name, 0, {}, {}};
        addViewArgs(f, c, where);
        return {f};
    }
    const json& path = c["path"];
    if (!path.is_array() || path.empty()) fail(where, "'path' must be a non-empty array");
    std::vector<CameraFrame> frames;
    for (size_t k = 0; k < path.size(); ++k) {
        std::string at = where + ".path[" + std::to_string(k) + "]";
        onlyKeys(path[k], {"position", "look_at", "up", "fov"}, at);
        CameraFrame f{name, int(k), {}, {}};
        addViewArgs(f, path[k], at);
        frames.push_back(f);
    }
    return frames;
}

std::vector<Setting> settingsOf(const json& doc, const std::string& file) {
    if (!doc.contains("settings")) return {{"", {}, ""}};
    const json& list = doc["settings"];
    if (!list.is_array() || list.empty()) fail(file, "'settings' must be a non-empty array");
    std::vector<Setting> settings;
    for (size_t i = 0; i < list.size(); ++i) {
        std::string where = file + ": settings[" + std::to_string(i) + "]";
        onlyKeys(list[i], {"name", "args"}, where);
        Setting s{"set" + std::to_string(i), {}, where + ": 'args'"};
        if (list[i].contains("name")) s.name = numberText(list[i]["name"], where);
        if (list[i].contains("args")) s.args = argList(list[i]["args"], s.where);
        settings.push_back(s);
    }
    return settings;
}

std::vector<std::string> scenesOf(const json& doc, const std::string& folder,
                                  const std::string& file) {
    if (!doc.contains("scenes") || !doc["scenes"].is_array() || doc["scenes"].empty())
        fail(file, "needs 'scenes': a non-empty array of scene paths");
    std::vector<std::string> scenes;
    for (const json& s : doc["scenes"]) {
        if (!s.is_string()) fail(file, "'scenes' must hold strings");
        fs::path p = fs::path(folder) / s.get<std::string>();
        std::error_code ec;
        if (!fs::is_regular_file(p, ec)) fail(file, "scene '" + p.string() + "' does not exist");
        scenes.push_back(fs::absolute(p).lexically_normal().string());
    }
    return scenes;
}

}  // namespace

std::string expandOutputName(const std::string& pattern, const OutputVariables& vars) {
    std::string out;
    for (size_t i = 0; i < pattern.size(); ++i) {
        if (pattern[i] != '{') {
            out += pattern[i];
            continue;
        }
        size_t close = pattern.find('}', i);
        if (close == std::string::npos) throw FarmInputError("unclosed '{' in '" + pattern + "'");
        std::string name = pattern.substr(i + 1, close - i - 1), width;
        bool widthGiven = false;
        if (size_t colon = name.find(':'); colon != std::string::npos)
            width = name.substr(colon + 1), name = name.substr(0, colon), widthGiven = true;
        if (name == "frame" || name == "index") {
            // A width of digits, at most 12 ({frame:012} too; {frame:} is 0, as it was):
            // '{frame:-4}' made fmt pad to 4e9 characters.
            const bool digitsOnly =
                width.size() <= 4 && std::all_of(width.begin(), width.end(),
                                                 [](char c) { return c >= '0' && c <= '9'; });
            const int digits = digitsOnly && !width.empty() ? std::stoi(width) : 0;
            if (!digitsOnly || digits > 12)
                throw FarmInputError("'{" + name + ":" + width + "}' in '" + pattern +
                                     "': the width is a number of digits from 0 to 12, e.g. {" +
                                     name + ":04}");
            int value = name == "frame" ? vars.frame : vars.index;
            out += fmt::format("{:0{}}", value, digits);
        } else if (name == "scene" || name == "camera" || name == "settings") {
            if (widthGiven)
                throw FarmInputError("'{" + name + ":" + width + "}' in '" + pattern +
                                     "': only {frame} and {index} take a width");
            out += name == "scene" ? vars.scene : name == "camera" ? vars.camera : vars.settings;
        } else {
            throw FarmInputError("unknown variable '{" + name + "}' in '" + pattern +
                                 "' (known: scene camera frame settings index)");
        }
        i = close;
    }
    return out;
}

std::vector<RenderTask> expandJobText(const std::string& text, const std::string& folder,
                                      const std::string& file, std::vector<TaskOrigin>* origins) {
    json doc = json::parse(text, nullptr, false);
    if (doc.is_discarded()) fail(file, "is not valid JSON");
    onlyKeys(doc, {"output", "scenes", "args", "cameras", "settings"}, file);
    if (!doc.contains("output") || !doc["output"].is_string())
        fail(file, "needs 'output': the output name pattern, e.g. \"out/{scene}_{frame:04}\"");
    std::vector<std::string> scenes = scenesOf(doc, folder, file);
    std::vector<std::string> common;
    if (doc.contains("args")) common = argList(doc["args"], file + ": 'args'");
    std::vector<CameraFrame> frames{{"default", 0, {}, {}}};
    if (doc.contains("cameras")) {
        if (!doc["cameras"].is_array() || doc["cameras"].empty())
            fail(file, "'cameras' must be a non-empty array");
        frames.clear();
        for (size_t i = 0; i < doc["cameras"].size(); ++i)
            for (CameraFrame& f : cameraFrames(doc["cameras"][i], i, file)) frames.push_back(f);
    }
    std::vector<Setting> settings = settingsOf(doc, file);
    std::vector<RenderTask> tasks;
    std::set<std::string> outputs;
    for (const std::string& scene : scenes)
        for (const CameraFrame& f : frames)
            for (const Setting& s : settings) {
                OutputVariables vars{fs::path(scene).stem().string(), f.camera, s.name, f.frame,
                                     int(tasks.size())};
                std::string name;
                try {
                    name = expandOutputName(doc["output"].get<std::string>(), vars);
                } catch (const FarmInputError& e) {
                    fail(file, e.what());
                }
                RenderTask t{scene, common,
                             fs::absolute(fs::path(folder) / name).lexically_normal()};
                t.args.insert(t.args.end(), f.args.begin(), f.args.end());
                t.args.insert(t.args.end(), s.args.begin(), s.args.end());
                if (origins) {
                    TaskOrigin o;
                    if (!common.empty()) o.sources.push_back({file + ": 'args'", common});
                    o.sources.insert(o.sources.end(), f.sources.begin(), f.sources.end());
                    if (!s.args.empty()) o.sources.push_back({s.where, s.args});
                    o.label =
                        fmt::format("{}: the render of scene '{}', camera '{}', frame {}{}", file,
                                    fs::path(scene).filename().string(), f.camera, f.frame,
                                    s.name.empty() ? "" : ", settings '" + s.name + "'");
                    origins->push_back(std::move(o));
                }
                if (!outputs.insert(t.output).second)
                    fail(file, "two renders write '" + t.output +
                                   "': add {scene}, {camera}, {frame} or {settings} to 'output'");
                tasks.push_back(t);
            }
    return tasks;
}

std::vector<RenderTask> readJobFile(const std::string& path, std::vector<TaskOrigin>* origins) {
    std::string folder = fs::path(path).parent_path().string();
    return expandJobText(readFileText(path), folder.empty() ? "." : folder, path, origins);
}

}  // namespace kiln::farm
