#include "renderer/checkpoint.h"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "color/atomic_file.h"

namespace kiln {
namespace {

constexpr char kMagic[8] = {'K', 'I', 'L', 'N', 'C', 'K', 'P', 'T'};

// CRC-32 of the bytes so far and n more. (zlib restarts the CRC on a null pointer, which an empty
// buffer may have: skipped.)
uLong checksum(uLong crc, const void* data, size_t n) {
    return n ? crc32_z(crc, static_cast<const Bytef*>(data), n) : crc;
}

// Header values go one per line: newlines and backslashes escaped.
std::string escape(const std::string& v) {
    std::string out;
    for (char c : v) {
        if (c == '\\')
            out += "\\\\";
        else if (c == '\n')
            out += "\\n";
        else
            out += c;
    }
    return out;
}

std::string unescape(const std::string& v) {
    std::string out;
    for (size_t i = 0; i < v.size(); ++i) {
        if (v[i] == '\\' && i + 1 < v.size())
            out += v[++i] == 'n' ? '\n' : v[i];
        else
            out += v[i];
    }
    return out;
}

std::string number(double v) { return fmt::format("{:.17g}", v); }

std::string vec(const Vec3& v) { return number(v.x) + " " + number(v.y) + " " + number(v.z); }

// Name, size and CRC-32 of a file's bytes: a scene edited since the checkpoint is another scene.
std::string fileIdentity(const std::string& path, const std::string& name = std::string()) {
    std::ifstream in(path, std::ios::binary);
    // A folder opens and reads as 0 bytes: its "identity" would pass for an empty scene's.
    if (!in || !std::filesystem::is_regular_file(path))
        throw std::runtime_error(path + ": cannot read for the checkpoint fingerprint");
    uLong crc = crc32(0, nullptr, 0);
    uint64_t size = 0;
    std::vector<char> chunk(1 << 20);
    while (in.read(chunk.data(), std::streamsize(chunk.size())) || in.gcount() > 0) {
        crc = crc32(crc, reinterpret_cast<const Bytef*>(chunk.data()), uInt(in.gcount()));
        size += uint64_t(in.gcount());
    }
    return fmt::format("{} ({} bytes, crc32 {:08x})",
                       name.empty() ? std::filesystem::path(path).filename().string() : name, size,
                       crc);
}

std::string headerText(const CheckpointInfo& info) {
    std::string h;
    auto put = [&h](const std::string& k, const std::string& v) {
        h += k + "=" + escape(v) + "\n";
    };
    for (const auto& [k, v] : info.fingerprint) put("fp." + k, v);
    put("aov_mask", std::to_string(info.aovs.mask));
    put("aov_bounce_layers", std::to_string(info.aovs.bounceLayers));
    // Only with --denoise-aovs: other checkpoints keep the header they had.
    if (info.aovs.denoisedLight) put("aov_denoised_light", std::to_string(info.aovs.denoisedLight));
    for (auto [k, v] : {std::pair<const char*, int>{"full_width", info.fullWidth},
                        {"full_height", info.fullHeight},
                        {"origin_x", info.originX},
                        {"origin_y", info.originY},
                        {"width", info.width},
                        {"height", info.height},
                        {"sample_start", info.sampleStart},
                        {"sample_end", info.sampleEnd},
                        {"complete", int(info.complete)},
                        {"film_scale_exponent", info.filmScaleExponent}})
        put(k, std::to_string(v));
    put("rays", std::to_string(info.rays));
    put("nonfinite_samples", std::to_string(info.nonFiniteSamples));
    put("seconds", number(info.seconds));
    for (const auto& [k, v] : info.metadata) put("meta." + k, v);
    return h;
}

// Reads exactly n bytes, folding them into the checksum.
class Reader {
  public:
    explicit Reader(const std::string& path) : path_(path), in_(std::fopen(path.c_str(), "rb")) {
        if (!in_) throw CheckpointError(path + ": cannot open checkpoint: " + std::strerror(errno));
    }
    ~Reader() { std::fclose(in_); }
    void read(void* to, size_t n) {
        if (std::fread(to, 1, n, in_) != n)
            throw CheckpointError(path_ + ": checkpoint is truncated");
        crc_ = checksum(crc_, to, n);
    }
    template <class T>
    T value() {
        T v;
        read(&v, sizeof v);
        return v;
    }
    uLong crc() const { return crc_; }

  private:
    std::string path_;
    FILE* in_;
    uLong crc_ = crc32(0, nullptr, 0);
};

int toInt(const std::map<std::string, std::string>& h, const std::string& key,
          const std::string& path) {
    auto it = h.find(key);
    if (it == h.end()) throw CheckpointError(path + ": checkpoint header lacks " + key);
    try {
        return std::stoi(it->second);
    } catch (const std::exception&) {
        throw CheckpointError(path + ": checkpoint header has a bad " + key);
    }
}

CheckpointInfo parseHeader(const std::string& text, const std::string& path) {
    std::map<std::string, std::string> h;
    CheckpointInfo info;
    size_t at = 0;
    while (at < text.size()) {
        size_t end = text.find('\n', at), eq = text.find('=', at);
        if (end == std::string::npos || eq > end)
            throw CheckpointError(path + ": checkpoint header is malformed");
        std::string key = text.substr(at, eq - at),
                    value = unescape(text.substr(eq + 1, end - eq - 1));
        if (key.rfind("fp.", 0) == 0)
            info.fingerprint.emplace_back(key.substr(3), value);
        else if (key.rfind("meta.", 0) == 0)
            info.metadata[key.substr(5)] = value;
        else
            h[key] = value;
        at = end + 1;
    }
    info.aovs.mask = uint32_t(std::stoul(h["aov_mask"].empty() ? "0" : h["aov_mask"]));
    info.aovs.bounceLayers = toInt(h, "aov_bounce_layers", path);
    info.aovs.denoisedLight =
        h.count("aov_denoised_light") ? uint32_t(toInt(h, "aov_denoised_light", path)) : 0u;
    info.fullWidth = toInt(h, "full_width", path), info.fullHeight = toInt(h, "full_height", path);
    info.originX = toInt(h, "origin_x", path), info.originY = toInt(h, "origin_y", path);
    info.width = toInt(h, "width", path), info.height = toInt(h, "height", path);
    info.sampleStart = toInt(h, "sample_start", path),
    info.sampleEnd = toInt(h, "sample_end", path);
    info.complete = toInt(h, "complete", path) != 0;
    // Absent in checkpoints from before films had a scale: those held light unscaled.
    info.filmScaleExponent =
        h.count("film_scale_exponent") ? toInt(h, "film_scale_exponent", path) : 0;
    info.rays = std::strtoull(h["rays"].c_str(), nullptr, 10);
    info.nonFiniteSamples = std::strtoull(h["nonfinite_samples"].c_str(), nullptr, 10);
    info.seconds = std::strtod(h["seconds"].c_str(), nullptr);
    if (info.width <= 0 || info.height <= 0 || info.width > 32768 || info.height > 32768 ||
        info.originX < 0 || info.originY < 0 || info.originX + info.width > info.fullWidth ||
        info.originY + info.height > info.fullHeight || info.sampleStart < 0 ||
        info.sampleEnd < info.sampleStart || info.aovs.bounceLayers < 0 ||
        info.aovs.bounceLayers > kMaxBounceLayers)
        throw CheckpointError(path + ": checkpoint header holds an impossible region or range");
    return info;
}

CheckpointInfo readHeader(Reader& in, const std::string& path) {
    char magic[8];
    in.read(magic, sizeof magic);
    if (std::memcmp(magic, kMagic, sizeof magic) != 0)
        throw CheckpointError(path + ": not a kiln checkpoint");
    uint32_t format = in.value<uint32_t>();
    if (format != kCheckpointFormat)
        throw CheckpointError(path + ": checkpoint format " + std::to_string(format) +
                              ", this kiln reads format " + std::to_string(kCheckpointFormat));
    uint64_t bytes = in.value<uint64_t>();
    if (bytes > (64u << 20)) throw CheckpointError(path + ": checkpoint header is malformed");
    std::string text(bytes, '\0');
    in.read(text.data(), bytes);
    uint32_t expected = uint32_t(in.crc());
    if (in.value<uint32_t>() != expected)
        throw CheckpointError(path + ": checkpoint checksum mismatch (the header is corrupted)");
    return parseHeader(text, path);
}

}  // namespace

std::string CheckpointInfo::regionText() const {
    return std::to_string(width) + "x" + std::to_string(height) + "+" + std::to_string(originX) +
           "+" + std::to_string(originY) + " of " + std::to_string(fullWidth) + "x" +
           std::to_string(fullHeight);
}

namespace {

std::atomic<uint64_t>& checksumCounter() {
    static std::atomic<uint64_t> count{0};
    return count;
}

}  // namespace

uint64_t sceneChecksumCount() { return checksumCounter().load(); }

namespace {

// The files besides the scene file and the --env map, each once (the same canonical path), as
// opened: named by the link a scene names, not its target (a farm node may hold a copy there).
std::vector<std::string> otherInputs(const std::string& scenePath, const LoadOptions& load,
                                     const Scene& scene) {
    namespace fs = std::filesystem;
    auto canonical = [](const std::string& p) {
        std::error_code ec;
        fs::path c = fs::weakly_canonical(p, ec);
        return ec ? fs::path(p) : c;
    };
    std::vector<std::string> opened = scene.inputFiles;
    for (const TextureSource& t : scene.textureSources)
        if (!t.bytes) opened.push_back(t.name);
    std::set<fs::path> seen;
    for (const std::string& known : {scenePath, load.environmentMap})
        if (!known.empty()) seen.insert(canonical(known));
    std::vector<std::string> files;
    for (const std::string& f : opened)
        if (seen.insert(canonical(f)).second) files.push_back(f);
    return files;
}

// The folder a scene's other files are named from (inputName): the scene file's, as written; empty
// where it cannot be made absolute (the files are then named by their filenames).
std::filesystem::path sceneFolder(const std::string& scenePath) {
    std::error_code ec;
    const std::filesystem::path scene = std::filesystem::absolute(scenePath, ec);
    return ec ? std::filesystem::path() : scene.lexically_normal().parent_path();
}

// A scene's other file named by its path from the scene's folder, as written (links not
// followed): two same-named files in different folders are told apart, and a farm node that mounts
// the tree elsewhere names them alike. A file outside that folder is named by its filename, as
// its path from the folder would depend on how deep the tree is mounted.
std::string inputName(const std::string& path, const std::filesystem::path& folder) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path file = fs::absolute(path, ec).lexically_normal();
    const fs::path relative = ec || folder.empty() ? fs::path() : file.lexically_relative(folder);
    const bool inside = !relative.empty() && *relative.begin() != "..";
    return inside ? relative.generic_string() : fs::path(path).filename().string();
}

// A file the loader could not open renders without it: that is its identity, not an error.
std::string inputIdentity(const std::string& path, const std::filesystem::path& folder) {
    const std::string name = inputName(path, folder);
    if (!std::filesystem::is_regular_file(path)) return name + " (absent)";
    if (!std::ifstream(path, std::ios::binary)) return name + " (unreadable)";
    return fileIdentity(path, name);
}

}  // namespace

SceneFileIdentity topFileIdentity(const std::string& scenePath, const LoadOptions& load) {
    ++checksumCounter();
    return {fileIdentity(scenePath),
            load.environmentMap.empty() ? "none" : fileIdentity(load.environmentMap), ""};
}

SceneFileIdentity withInputIdentities(SceneFileIdentity top, const std::string& scenePath,
                                      const LoadOptions& load, const Scene& scene) {
    // Sorted by identity, not path: a farm node that mounts the files elsewhere lists them in the
    // same order.
    std::vector<std::string> inputs;
    const std::filesystem::path folder = sceneFolder(scenePath);
    for (const std::string& f : otherInputs(scenePath, load, scene))
        inputs.push_back(inputIdentity(f, folder));
    std::sort(inputs.begin(), inputs.end());
    top.inputs.clear();
    for (const std::string& i : inputs) top.inputs += (top.inputs.empty() ? "" : "; ") + i;
    return top;
}

SceneFileIdentity sceneFileIdentity(const std::string& scenePath, const LoadOptions& load,
                                    const Scene& scene) {
    return withInputIdentities(topFileIdentity(scenePath, load), scenePath, load, scene);
}

Fingerprint checkpointFingerprint(const RenderJob& job, const std::string& scenePath,
                                  const LoadOptions& load) {
    return checkpointFingerprint(job, sceneFileIdentity(scenePath, load, job.scene()), load);
}

namespace {

std::string cameraText(const Camera& c) {
    return vec(c.position) + " / " + vec(c.forward) + " / " + vec(c.up) + " / fov " +
           number(c.hFovDeg) + " " + number(c.vFovDeg) + " / lens " + number(c.apertureRadius) +
           " " + number(c.focalDistance) +
           (c.orthographic()
                ? " / orthographic " + number(c.orthoHalfWidth) + " " + number(c.orthoHalfHeight)
                : "");
}

std::string aovText(const AovRequest& a) {
    return std::to_string(a.mask) + " bounces " + std::to_string(a.bounceLayers) + " depth " +
           toString(a.depth) + (a.transparent ? " transparent" : "") +
           (a.denoisedLight ? " denoised " + AovRequest::namesOf(a.denoisedLight) : "");
}

// The fingerprint in its one order; without a job, only the fields the options and the files
// decide (those a resume is checked against before the load). With a job, o is its options (light
// samples resolved).
Fingerprint fingerprintOf(const RenderJobOptions& o, const RenderJob* job,
                          const SceneFileIdentity& files, const LoadOptions& load) {
    const PathOptions& p = o.path;
    const RenderSettings& s = o.settings;
    Fingerprint f;
    auto put = [&f](const char* key, std::string value) { f.emplace_back(key, std::move(value)); };
    auto putJob = [&](const char* key, auto valueOf) {
        if (job) f.emplace_back(key, valueOf(*job));
    };
    put("kiln_version", KILN_VERSION);
    put("scene", files.scene);
    put("environment_map", files.environmentMap);
    put("environment_scale", number(load.environmentScale));
    put("environment_rotation", number(load.environmentRotationDeg));
    put("material_override", load.materialOverride.empty() ? "none" : load.materialOverride);
    putJob("camera", [](const RenderJob& j) { return cameraText(j.scene().camera); });
    put("resolution", std::to_string(s.width) + "x" + std::to_string(s.height));
    put("seed", std::to_string(s.seed));
    put("sampler", toString(s.sampler));
    putJob("integrator", [](const RenderJob& j) { return std::string(j.integrator().name()); });
    putJob("plan", [](const RenderJob& j) { return j.plan().compact(); });
    put("max_depth", std::to_string(p.maxDepth));
    // Its default is the plan's choice (resolvedLightSamples).
    putJob("light_samples", [&p](const RenderJob&) { return std::to_string(p.lightSamples); });
    put("sampling", toString(p.sampling));
    put("mis_heuristic", toString(p.heuristic));
    put("roulette", std::string(toString(p.roulette)) + " " + number(p.fixedContinuation) + " " +
                        std::to_string(p.rouletteMinBounces));
    put("accumulate_bounces", p.accumulateBounces ? "yes" : "no");
    put("microfacet", toString(p.microfacet));
    putJob("guiding", [](const RenderJob& j) { return std::string(j.guided() ? "on" : "off"); });
    put("aovs", aovText(o.aovs));
    putJob("film_scale",
           [](const RenderJob& j) { return "2^" + std::to_string(j.filmScaleExponent()); });
    put("adaptive", s.adaptiveText());
    // Only where there are such files: a checkpoint of a one-file scene keeps its fingerprint.
    if (job && !files.inputs.empty()) put("scene_inputs", files.inputs);
    return f;
}

}  // namespace

Fingerprint checkpointFingerprint(const RenderJob& job, const SceneFileIdentity& files,
                                  const LoadOptions& load) {
    return fingerprintOf(job.options(), &job, files, load);
}

Fingerprint fingerprintBeforeLoad(const RenderJobOptions& options, const SceneFileIdentity& files,
                                  const LoadOptions& load) {
    return fingerprintOf(options, nullptr, files, load);
}

namespace {

// The scene's other files (scene_inputs, "" for none) by name: an identity is "NAME (...)".
std::multimap<std::string, std::string> inputsByName(const std::string& list) {
    std::multimap<std::string, std::string> items;
    for (size_t b = 0, e; b < list.size(); b = e + 2) {
        e = std::min(list.find("; ", b), list.size());
        std::string item = list.substr(b, e - b);
        items.emplace(item.substr(0, item.rfind(" (")), item);
    }
    return items;
}

// One file of the two lists, not the whole lists (a scene may read many): an edited file first,
// then one only one side read. Compared by name, so a file added or gone names itself, not the
// file that took its place in the sorted list.
std::string inputsDifference(const std::string& saved, const std::string& here,
                             const std::string& savedName) {
    const auto a = inputsByName(saved), b = inputsByName(here);
    auto identities = [](const auto& items, const std::string& name) {
        std::vector<std::string> out;
        for (auto [it, end] = items.equal_range(name); it != end; ++it) out.push_back(it->second);
        return out;
    };
    auto quoted = [](const std::vector<std::string>& ids) {
        std::string text;
        for (const std::string& id : ids) text += (text.empty() ? "'" : ", '") + id + "'";
        return text;
    };
    std::set<std::string> names;
    for (const auto& items : {a, b})
        for (const auto& [name, id] : items) names.insert(name);
    for (bool bothSides : {true, false})
        for (const std::string& name : names) {
            const auto was = identities(a, name), is = identities(b, name);
            if (was == is || (was.empty() || is.empty()) == bothSides) continue;
            return fmt::format("scene_inputs: {} in {}, {} here",
                               was.empty() ? "no file " + name : quoted(was), savedName,
                               is.empty() ? "no file " + name : quoted(is));
        }
    return "";
}

// The fingerprint's AOV field (aovText: the mask first, as every checkpoint holds it) with the
// mask's AOVs named, for a message: "60423 bounces 0" said nothing to a reader.
std::string aovWords(const std::string& field) {
    const size_t space = field.find(' ');
    const std::string head = field.substr(0, space);
    if (head.empty() || head.size() > 10 ||
        head.find_first_not_of("0123456789") != std::string::npos)
        return field;
    const unsigned long long mask = std::stoull(head);
    if (mask > 0xffffffffull) return field;
    return AovRequest::allNamesOf(uint32_t(mask)) +
           (space == std::string::npos ? "" : field.substr(space));
}

}  // namespace

std::string fingerprintDifference(const Fingerprint& saved, const Fingerprint& here,
                                  const std::string& savedName) {
    const std::map<std::string, std::string> theirs(saved.begin(), saved.end()),
        ours(here.begin(), here.end());
    auto differ = [&](const std::string& key, const std::string* was, const std::string* is) {
        if (key == "scene_inputs")
            return inputsDifference(was ? *was : "", is ? *is : "", savedName);
        auto shown = [&](const std::string* v) {
            return v ? "'" + (key == "aovs" ? aovWords(*v) : *v) + "'" : std::string("absent");
        };
        return key + " is " + shown(was) + " in " + savedName + ", " + shown(is) + " here";
    };
    for (const auto& [key, value] : here) {
        auto it = theirs.find(key);
        if (it == theirs.end() || it->second != value)
            return differ(key, it == theirs.end() ? nullptr : &it->second, &value);
    }
    for (const auto& [key, value] : saved)
        if (!ours.count(key)) return differ(key, &value, nullptr);
    return "";
}

CheckpointInfo checkpointInfo(const Fingerprint& fingerprint, const RenderJobOptions& options,
                              const Film& film, const RenderStats& totals, const Metadata& meta) {
    CheckpointInfo info;
    info.fingerprint = fingerprint;
    info.aovs = film.layout().request();
    info.fullWidth = film.fullWidth(), info.fullHeight = film.fullHeight();
    info.originX = film.originX(), info.originY = film.originY();
    info.width = film.width(), info.height = film.height();
    info.sampleStart = options.settings.sampleStart, info.sampleEnd = options.settings.spp;
    info.filmScaleExponent = film.scaleExponent();
    info.complete = totals.complete;
    info.rays = totals.rays, info.nonFiniteSamples = totals.nonFiniteSamples;
    info.seconds = totals.seconds;
    info.metadata = meta;
    return info;
}

void writeCheckpoint(const std::string& path, const CheckpointInfo& info, const Film& film) {
    AtomicFile file(path);
    uLong crc = crc32(0, nullptr, 0);
    auto put = [&](const void* data, size_t n) {
        file.write(data, n);
        crc = checksum(crc, data, n);
    };
    std::string header = headerText(info);
    uint64_t headerBytes = header.size();
    put(kMagic, sizeof kMagic);
    put(&kCheckpointFormat, sizeof kCheckpointFormat);
    put(&headerBytes, sizeof headerBytes);
    put(header.data(), header.size());
    uint32_t headerChecksum = uint32_t(crc);  // the header alone can be trusted before the film
    put(&headerChecksum, sizeof headerChecksum);
    std::vector<FilmBuffer> buffers = film.buffers();
    uint32_t count = uint32_t(buffers.size());
    put(&count, sizeof count);
    for (const FilmBuffer& b : buffers) {
        uint32_t nameBytes = uint32_t(b.name.size());
        uint8_t rule = uint8_t(b.rule);
        uint64_t bytes = b.bytes(film.pixelCount());
        put(&nameBytes, sizeof nameBytes);
        put(b.name.data(), nameBytes);
        put(&rule, 1);
        put(&b.elementBytes, sizeof b.elementBytes);
        put(&b.perPixel, sizeof b.perPixel);
        put(&bytes, sizeof bytes);
        put(b.data, bytes);
    }
    uint32_t checksum = uint32_t(crc);
    file.write(&checksum, sizeof checksum);
    file.commit();
}

CheckpointInfo readCheckpointInfo(const std::string& path) {
    Reader in(path);
    return readHeader(in, path);
}

namespace {

// The next buffer's header; throws unless it is the film's buffer b for pixels pixels.
void expectBuffer(Reader& in, const FilmBuffer& b, size_t pixels, const std::string& path) {
    uint32_t nameBytes = in.value<uint32_t>();
    if (nameBytes > 256) throw CheckpointError(path + ": checkpoint is malformed");
    std::string name(nameBytes, '\0');
    in.read(name.data(), nameBytes);
    uint8_t rule = in.value<uint8_t>();
    uint32_t elementBytes = in.value<uint32_t>(), perPixel = in.value<uint32_t>();
    uint64_t bytes = in.value<uint64_t>();
    if (name != b.name || rule != uint8_t(b.rule) || elementBytes != b.elementBytes ||
        perPixel != b.perPixel || bytes != b.bytes(pixels))
        throw CheckpointError(path + ": checkpoint buffer '" + name +
                              "' does not match this kiln's '" + b.name + "'");
}

void expectBufferCount(Reader& in, size_t count, const std::string& path) {
    if (in.value<uint32_t>() != count)
        throw CheckpointError(path + ": checkpoint holds other film buffers than this kiln's");
}

void expectChecksum(Reader& in, const std::string& path) {
    uLong expected = in.crc();
    if (in.value<uint32_t>() != uint32_t(expected))
        throw CheckpointError(path + ": checkpoint checksum mismatch (the file is corrupted)");
}

}  // namespace

Film readCheckpoint(const std::string& path, CheckpointInfo& info) {
    Reader in(path);
    info = readHeader(in, path);
    Film film(info.width, info.height, info.aovs);
    film.setRegion(info.originX, info.originY, info.fullWidth, info.fullHeight);
    film.setScaleExponent(info.filmScaleExponent);
    std::vector<FilmBuffer> buffers = film.buffers();
    expectBufferCount(in, buffers.size(), path);
    for (const FilmBuffer& b : buffers) {
        expectBuffer(in, b, film.pixelCount(), path);
        in.read(b.data, b.bytes(film.pixelCount()));
    }
    expectChecksum(in, path);
    return film;
}

void mergeCheckpoint(const std::string& path, Film& into, CheckpointInfo& info) {
    Reader in(path);
    info = readHeader(in, path);
    size_t at = [&] {
        try {
            return into.placeShard(info.originX, info.originY, info.width, info.height,
                                   info.fullWidth, info.fullHeight);
        } catch (const std::invalid_argument& e) {
            throw CheckpointError(path + ": " + e.what());
        }
    }();
    if (info.filmScaleExponent != into.scaleExponent())
        throw CheckpointError(
            fmt::format("{}: its film holds light scaled by 2^{}, the merged "
                        "film 2^{}",
                        path, info.filmScaleExponent, into.scaleExponent()));
    std::vector<FilmBuffer> buffers = into.buffers();
    size_t width = size_t(info.width);
    expectBufferCount(in, buffers.size(), path);
    std::vector<char> row;
    for (const FilmBuffer& b : buffers) {
        expectBuffer(in, b, width * size_t(info.height), path);
        row.resize(b.bytes(width));
        // A row at a time straight into the merged film: no second film in memory.
        for (int y = 0; y < info.height; ++y) {
            in.read(row.data(), row.size());
            combineRun(b, row.data(), at + size_t(y) * size_t(into.width()), width,
                       into.sampleCounts());
        }
    }
    expectChecksum(in, path);
}

}  // namespace kiln
