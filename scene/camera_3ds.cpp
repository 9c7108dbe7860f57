// 3DS cameras read from the file's own chunks: Assimp 5.2 resets a 3DS camera's target to +Z and
// reads its lens as an angle, so kiln takes position, target, bank and lens from the editor chunk.
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "scene/importers.h"

namespace kiln {
namespace {

constexpr uint16_t kMain = 0x4D4D, kEditor = 0x3D3D, kObject = 0x4000, kCamera = 0x4700;

struct Chunks {
    const std::vector<char>& bytes;

    template <typename T>
    T read(size_t at) const {
        T v;
        std::memcpy(&v, bytes.data() + at, sizeof v);  // 3DS is little-endian, as kiln's hosts
        return v;
    }

    // Searches [begin, end) for the camera chunk of the object called `name`.
    std::optional<Camera3ds> find(size_t begin, size_t end, const std::string& name,
                                  const std::string& object) const {
        for (size_t at = begin; at + 6 <= end;) {
            uint16_t id = read<uint16_t>(at);
            uint32_t length = read<uint32_t>(at + 2);
            if (length < 6 || length > end - at) return std::nullopt;  // garbled: Assimp decides
            size_t body = at + 6, stop = at + length;
            std::optional<Camera3ds> found;
            if (id == kMain || id == kEditor) {
                found = find(body, stop, name, object);
            } else if (id == kObject) {
                const char* text = bytes.data() + body;
                size_t len = strnlen(text, stop - body);
                if (body + len < stop) found = find(body + len + 1, stop, name, {text, len});
            } else if (id == kCamera && object == name && length >= 6 + 8 * 4) {
                Camera3ds c;
                for (int i = 0; i < 3; ++i) {
                    c.position[i] = read<float>(body + 4 * size_t(i));
                    c.target[i] = read<float>(body + 12 + 4 * size_t(i));
                }
                c.bankDeg = read<float>(body + 24);
                c.lensMm = read<float>(body + 28);
                found = c;
            }
            if (found) return found;
            at = stop;
        }
        return std::nullopt;
    }
};

}  // namespace

std::optional<Camera3ds> read3dsCamera(const std::string& path, const std::string& name) {
    std::ifstream in(path, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return Chunks{bytes}.find(0, bytes.size(), name, "");
}

float fovFrom3dsLens(float lensMm) {
    // lib3ds' rule (fov = 2400 / lens); 3DS writers store lens = 2400 / fov, so a 45 degree
    // camera reads back as 45 (assimp-testmodels' cameras: lens 53.333).
    return lensMm > 0 ? 2400.0f / lensMm : 45.0f;
}

}  // namespace kiln
