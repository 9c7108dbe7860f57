// Fuzzing the readers kiln implements itself (CGL COLLADA pass, ASCII and binary PLY, OBJ, .kiln):
// a deterministic mutator (fixed seeds) over small valid files; every mutant run through the kiln
// binary must end with exit 0, or exit 2 and a one-line error naming the file, never a signal or
// a hang.
#include <cstdint>
#include <fstream>
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
    return {{"dae", dae}, {"ply", ply}, {"ply", binaryPly()}, {"obj", obj}, {"kiln", kiln}};
}

TEST(Fuzz, MutatedInputsEndInAnErrorOrAnImageNeverASignal) {
    auto dir = test::scratchDir();
    test::writeFile(dir / "base.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n");
    constexpr int kPerSeed = 36;  // 180 cases: about 25 s on two idle cores (process start-up)
    Rng rng{0x9E3779B97F4A7C15ull};
    std::vector<std::string> cases;
    for (const auto& [ext, text] : seeds())
        for (int i = 0; i < kPerSeed; ++i) {
            std::string name = "case" + std::to_string(cases.size()) + "." + ext;
            test::writeFile(dir / name, mutate(text, rng));
            cases.push_back(name);
        }
    // Two at a time (the suite's two cores); a hang is killed after 30 s and reads as exit 137.
    std::string script = "cd '" + dir.string() + "' && ls case*.* | xargs -P 2 -I{} sh -c '" +
                         "timeout -s KILL 30 " + KILN_BINARY +
                         " info {} >/dev/null 2>{}.err; echo $? >{}.rc'";
    ASSERT_EQ(std::system(script.c_str()), 0);
    int errors = 0, ok = 0;
    for (const std::string& name : cases) {
        std::string rcText = readAll(dir / (name + ".rc")), err = readAll(dir / (name + ".err"));
        int rc = std::atoi(rcText.c_str());
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
