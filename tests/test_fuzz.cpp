// Fuzzing the readers kiln implements itself (CGL COLLADA pass, ASCII and binary PLY, OBJ, .kiln),
// glTF through Assimp, job files (kiln batch) and checkpoints (kiln render --resume): a
// deterministic mutator (fixed seeds) over small valid files; every mutant run through the kiln
// binary must end with exit 0, or exit 2 and a one-line error naming the file, never a signal or
// a hang. The reproducers of issue #33 run beside them, each with the exit code it must give.
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "test_support.h"

namespace kiln {
namespace {

// xorshift64*: the same sequence on every platform (std distributions are not portable).
struct Rng {
    uint64_t s;
    uint64_t next() {
        s ^= s >> 12, s ^= s << 25, s ^= s >> 27;
        return s * 2685821657736338717ull;
    }
    size_t below(size_t n) { return n ? size_t(next() % n) : 0; }
};

// Tokens that broke readers before: signs, huge and non-finite numbers, numeric prefixes,
// separators, XML structure.
const std::vector<std::string> kTokens = {
    "-1",  "0",    "-6",  "1e39",  "-1e39", "nan",          "inf", "4294967295",
    "1x",  "1,5",  "2.7", "abc",   "",      "99999999999",  "<",   ">",
    "\"",  "</p>", "&",   "\n",    " ",     "end_header\n", "\0",  "3.9",
    "1e7", "-0",   "0x1", "1e-320"};

std::string mutate(std::string s, Rng& rng) {
    int edits = rng.below(4) == 0 ? 2 : 1;
    for (int e = 0; e < edits && !s.empty(); ++e) {
        size_t at = rng.below(s.size()), len = 1 + rng.below(std::min<size_t>(16, s.size() - at));
        switch (rng.below(11) / 2) {  // truncation (10) half as often
            case 0:                   // flip a byte
                s[at] = char(s[at] ^ (1 << rng.below(8)));
                break;
            case 1:  // delete a run
                s.erase(at, len);
                break;
            case 2:  // duplicate a run
                s.insert(at, s.substr(at, len));
                break;
            case 3:  // insert a token
                s.insert(at, kTokens[rng.below(kTokens.size())]);
                break;
            case 4: {  // replace the number under `at` by a token
                size_t b = at, end = at;
                while (b > 0 && std::isdigit(static_cast<unsigned char>(s[b - 1]))) --b;
                while (end < s.size() && std::isdigit(static_cast<unsigned char>(s[end]))) ++end;
                s.replace(b, std::max<size_t>(end - b, 1), kTokens[rng.below(kTokens.size())]);
                break;
            }
            default:  // truncate
                s.resize(at);
                break;
        }
    }
    return s;
}

std::string readAll(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string binaryPly() {
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty "
        "float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\n"
        "end_header\n";
    float v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    s.append(reinterpret_cast<const char*>(v), sizeof v);
    for (int f : {0, 1}) {
        int32_t idx[3] = {0, 1, 2 + f};
        s += char(3);
        s.append(reinterpret_cast<const char*>(idx), sizeof idx);
    }
    return s;
}

// The small valid inputs, one per format kiln reads itself.
std::vector<std::pair<std::string, std::string>> seeds() {
    std::string dae = R"(<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit meter="1"/><up_axis>Z_UP</up_axis></asset>
<library_cameras><camera id="c" name="c"><optics><technique_common><perspective><xfov>40</xfov><aspect_ratio>1.3</aspect_ratio><znear>0.1</znear></perspective></technique_common></optics></camera></library_cameras>
<library_lights><light id="l"><extra><technique profile="CGL"><area><color>1 1 1</color></area></technique></extra></light></library_lights>
<library_effects><effect id="e"><profile_COMMON><technique sid="t"><phong><diffuse><color>0.5 0.5 0.5 1</color></diffuse></phong></technique></profile_COMMON><extra><technique profile="CGL"><glass><reflectance>1 1 1</reflectance><transmittance>1 1 1</transmittance><roughness>0</roughness><ior>1.5</ior></glass></technique></extra></effect></library_effects>
<library_materials><material id="m" name="m"><instance_effect url="#e"/></material></library_materials>
<library_geometries><geometry id="g" name="g"><mesh>
<source id="p"><float_array id="pa" count="12">0 0 0 1 0 0 0 1 0 0 0 1</float_array>
<technique_common><accessor source="#pa" count="4" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles material="m" count="2"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2 0 1 3</p></triangles>
</mesh></geometry>
<geometry id="s" name="s"><extra><technique profile="CGL"><sphere><radius>0.5</radius></sphere></technique></extra></geometry></library_geometries>
<library_visual_scenes><visual_scene id="vs">
<node id="n"><matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix><instance_geometry url="#g"><bind_material><technique_common><instance_material symbol="m" target="#m"/></technique_common></bind_material></instance_geometry></node>
<node id="sn"><translate>2 0 0</translate><instance_geometry url="#s"><bind_material><technique_common><instance_material symbol="m" target="#m"/></technique_common></bind_material></instance_geometry></node>
<node id="ln"><translate>0 0 3</translate><instance_light url="#l"/></node>
<node id="cn"><translate>0 -5 1</translate><rotate>1 0 0 90</rotate><instance_camera url="#c"/></node>
</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#vs"/></scene></COLLADA>
)";
    std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n";
    std::string obj =
        "# tetra\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\n"
        "o a\nf 1//1 2//2 3//3\ng b\nf 1//1 2//2 4//4\n";
    std::string kiln = R"(<kiln-scene>
<material name="g" kind="glass" ior="1.5"/>
<mesh file="base.obj" material="g"><fit center="0 0 0" size="2"/></mesh>
<instances file="base.obj" grid="2 1 2" spacing="3" translate="0 0 5"/>
<camera position="0 1 8" look-at="0 0 0" fov="40"/>
<light kind="point" radiance="5 5 5" position="0 4 0"/>
</kiln-scene>
)";
    // glTF through Assimp: a triangle placed by two nodes, its buffer embedded.
    std::string gltf =
        R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}], "nodes": [{"mesh": 0}, {"mesh": 0, "translation": [2, 0, 0]}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}], "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}], "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}], "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}, {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";
    return {{"dae", dae}, {"ply", ply},   {"ply", binaryPly()},
            {"obj", obj}, {"kiln", kiln}, {"gltf", gltf}};
}

// A job file for kiln batch: the output pattern and the scene are fixed (a mutant must not write
// outside its folder), the render entries after them are mutated.
const std::string kJobHead =
    R"({"output": "out/{camera}_{frame}_{settings}", "scenes": ["../base.obj"], )";
const std::string kJobTail =
    R"("args": ["-r", 4, 3, "-s", 1], "cameras": [{"name": "a", "position": [0.3, 0.3, 5], "look_at": [0.3, 0.3, 0], "up": [0, 1, 0], "fov": 40}], "settings": [{"name": "lo", "args": ["-m", 2]}]})";

// Job-file mutants that stay JSON (byte edits mostly break the syntax and test only the JSON
// parser): one or two of the tail's values, numbers and strings alike, replaced by a token, as a
// JSON number where it reads as one and a string otherwise; every other mutant a byte edit.
std::string mutateJob(const std::string& tail, Rng& rng) {
    if (rng.below(3) == 0) return mutate(tail, rng);
    static const std::vector<std::string> kValues = {
        "-1",          "0",       "1e39", "-1e39",          "4294967295",
        "99999999999", "2.7",     "-0",   "1e-320",         "nan",
        "abc",         "",        "-s",   "--fov",          "-r",
        "--up",        "--bogus", "-a",   "--sample-range", "180",
        "1x"};
    std::vector<std::pair<size_t, size_t>> values;  // [begin, end) of each scalar
    for (size_t i = 0; i < tail.size();) {
        if (tail[i] == '"') {
            size_t end = tail.find('"', i + 1);
            size_t after = tail.find_first_not_of(' ', end + 1);
            if (after == std::string::npos || tail[after] != ':') values.push_back({i, end + 1});
            i = end + 1;
        } else if (std::isdigit(static_cast<unsigned char>(tail[i])) || tail[i] == '-') {
            size_t end = tail.find_first_of(",]} ", i);
            values.push_back({i, end});
            i = end;
        } else {
            ++i;
        }
    }
    std::string out = tail;
    int edits = 1 + int(rng.below(2));
    for (int e = 0; e < edits; ++e) {
        auto [b, end] = values[rng.below(values.size())];
        const std::string& v = kValues[rng.below(kValues.size())];
        char* stop = nullptr;
        std::strtod(v.c_str(), &stop);
        bool number = !v.empty() && *stop == '\0' && v != "nan" && v.back() != '.' &&
                      v.find("1e-320") == std::string::npos;
        std::string replacement = number ? v : "\"" + v + "\"";
        out = tail.substr(0, b) + replacement + tail.substr(end);
        if (e == 0 && edits > 1) {  // a second edit on the original positions' text
            std::string again = out;
            auto [b2, end2] = values[rng.below(values.size())];
            if (b2 > end || end2 < b) {  // apart: apply to the edited text, positions shifted
                long shift = long(replacement.size()) - long(end - b);
                size_t s2 = b2 > end ? size_t(long(b2) + shift) : b2;
                size_t e2 = b2 > end ? size_t(long(end2) + shift) : end2;
                const std::string& v2 = kValues[rng.below(kValues.size())];
                again = out.substr(0, s2) + "\"" + v2 + "\"" + out.substr(e2);
            }
            return again;
        }
    }
    return out;
}

// Reproducers of issue #33, each with the exit code it must end with (2: one line naming it).
struct Reproducer {
    std::string name, text;
    int code;
};
std::vector<Reproducer> reproducers() {
    const std::string quad = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";
    const std::string triangle =
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 "
        "0\nendloop\nendfacet\nendsolid t\n";
    auto job = [](const std::string& tail) {
        return R"({"output": "out/{camera}", "scenes": ["../base.obj"], )" + tail + "}";
    };
    return {
        // OBJ normal index past the last vn (Assimp gave it another normal).
        {"rep_normals.obj", quad + "vn 0 0 1\nvn 0 0 -1\nf 1//1 2//1 3//1\nf 2//2 4//3 3//2\n", 2},
        // STL with an empty part beside a triangle.
        {"rep_empty_solid.stl", triangle + "solid e\nendsolid e\n", 0},
        {"rep_only_empty.stl", "solid e\nendsolid e\n", 2},
        // Job files with render values kiln render refuses, checked before any render.
        {"rep_spp0/job.json", job(R"("args": ["-r", 4, 3, "-s", 0])"), 2},
        {"rep_number/job.json", job(R"("args": ["-r", 4, 3, 7])"), 2},
        {"rep_up/job.json", job(R"("cameras": [{"position": [0, 0, 5], "up": [0, 1e39, 0]}])"), 2},
        {"rep_centre/job.json", job(R"("cameras": [{"turntable": 2, "centre": [1e39, 0, 0]}])"), 2},
        // A camera whose clip range excludes the scene: a warning, not an error.
        {"rep_clip.dae",
         R"(<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1"><asset><up_axis>Y_UP</up_axis></asset>
<library_cameras><camera id="c" name="c"><optics><technique_common><perspective><yfov>40</yfov><aspect_ratio>1</aspect_ratio><znear>0.1</znear><zfar>100</zfar></perspective></technique_common></optics></camera></library_cameras>
<library_geometries><geometry id="g"><mesh><source id="p"><float_array id="pa" count="9">-1 0 0 1 0 0 0 1 0</float_array><technique_common><accessor source="#pa" count="3" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source><vertices id="v"><input semantic="POSITION" source="#p"/></vertices><triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles></mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g"/></node><node id="cn"><translate>0 0 5</translate><scale>1000 1000 1000</scale><instance_camera url="#c"/></node></visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>)",
         0}};
}

TEST(Fuzz, MutatedInputsEndInAnErrorOrAnImageNeverASignal) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "base.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n");
    // A finished 8x6 render's checkpoint: the seed of the checkpoint mutants (kiln render
    // --resume).
    const std::string resume =
        std::string(KILN_BINARY) + " render base.obj -r 8 6 -s 2 -q --resume -o ";
    ASSERT_EQ(std::system(("cd '" + dir.string() + "' && " + resume + "seed 2>/dev/null").c_str()),
              0);
    const std::string checkpoint = readAll(dir / "seed.ckpt");
    ASSERT_FALSE(checkpoint.empty());
    constexpr int kPerSeed = 36;     // the six file formats: 216 cases
    constexpr int kPerRunSeed = 24;  // job files and checkpoints: 48 more (each one a render)
    Rng rng{0x9E3779B97F4A7C15ull};
    std::vector<std::string> cases;
    for (const auto& [ext, text] : seeds())
        for (int i = 0; i < kPerSeed; ++i) {
            std::string name = "case" + std::to_string(cases.size()) + "." + ext;
            test::writeFile(dir / name, mutate(text, rng));
            cases.push_back(name);
        }
    for (int i = 0; i < kPerRunSeed; ++i) {  // each job in its own folder: outputs never shared
        std::string name = "job" + std::to_string(i) + "/job.json";
        std::filesystem::create_directories(dir / ("job" + std::to_string(i)));
        test::writeFile(dir / name, kJobHead + mutateJob(kJobTail, rng));
        cases.push_back(name);
    }
    for (int i = 0; i < kPerRunSeed; ++i) {
        std::string name = "ckpt" + std::to_string(i) + ".ckpt";
        test::writeFile(dir / name, mutate(checkpoint, rng));
        cases.push_back(name);
    }
    std::map<std::string, int> expected;
    for (const Reproducer& r : reproducers()) {
        std::filesystem::create_directories((dir / r.name).parent_path());
        test::writeFile(dir / r.name, r.text);
        cases.push_back(r.name);
        expected[r.name] = r.code;
    }
    // What each case runs: a job file kiln batch, a checkpoint kiln render --resume, any other
    // file kiln info. Two at a time (the suite's two cores); a hang is killed after 30 s (137).
    test::writeFile(dir / "run.sh",
                    "case \"$1\" in\n"
                    "  *.json) timeout -s KILL 30 " +
                        std::string(KILN_BINARY) +
                        " batch \"$1\" -q ;;\n"
                        "  *.ckpt) timeout -s KILL 30 " +
                        resume +
                        "\"${1%.ckpt}\" ;;\n"
                        "  *) timeout -s KILL 30 " +
                        std::string(KILN_BINARY) +
                        " info \"$1\" ;;\n"
                        "esac >/dev/null 2>\"$1.err\"\necho $? >\"$1.rc\"\n");
    std::string list;
    for (const std::string& name : cases) list += name + "\n";
    test::writeFile(dir / "cases.txt", list);
    std::string script = "cd '" + dir.string() + "' && xargs -P 2 -I{} sh run.sh {} <cases.txt";
    ASSERT_EQ(std::system(script.c_str()), 0);
    int errors = 0, ok = 0;
    for (const std::string& name : cases) {
        std::string rcText = readAll(dir / (name + ".rc")), err = readAll(dir / (name + ".err"));
        int rc = std::atoi(rcText.c_str());
        if (auto want = expected.find(name); want != expected.end()) {
            EXPECT_EQ(rc, want->second) << name << ": " << err;
        }
        if (rc == 0) {
            ++ok;
            continue;
        }
        ++errors;
        EXPECT_EQ(rc, 2) << name << " ended with " << rc << " (" << (rc > 128 ? "signal" : "exit")
                         << "): " << err;
        EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << name << ": " << err;
        EXPECT_NE(err.find(name), std::string::npos) << name << " not named in: " << err;
    }
    // The mutator must reach both sides: a fuzzer whose every case fails to parse tests little.
    EXPECT_GT(ok, int(cases.size()) / 10);
    EXPECT_GT(errors, int(cases.size()) / 4);
    std::printf("fuzz: %zu cases, %d loaded, %d refused with exit 2\n", cases.size(), ok, errors);
}

}  // namespace
}  // namespace kiln
