// The lamps of a .blend file as Blender stores them, read from the file's own DNA (the struct
// layouts every .blend carries): Assimp 5.2 hands over a lamp's energy times its colour and
// nothing of its Distance or falloff, so kiln could not convert a Blender lamp the way Blender
// shows it. Only what the conversion needs is read: each Object's name and data pointer, each
// Lamp's type, mode, colour, energy, Distance, falloff type, sliders, gamma, spot size and area
// size. Plain and gzip-compressed files (zlib reads both), either byte order, 4- or 8-byte
// pointers.
#include <zlib.h>

#include <bit>
#include <cstring>
#include <map>
#include <optional>

#include "scene/importers.h"

namespace kiln {
namespace {

struct DnaField {
    std::string type, name;  // name as stored: "*data", "name[66]", "r"
};
struct DnaStruct {
    std::string type;
    std::vector<DnaField> fields;
};

class BlendReader {
  public:
    BlendReader(std::string bytes) : b_(std::move(bytes)) {}

    bool parse(std::string& reason) {
        if (b_.size() < 12 || b_.compare(0, 7, "BLENDER") != 0)
            return fail(reason, "no BLENDER header");
        pointer_ = b_[7] == '-' ? 8 : b_[7] == '_' ? 4 : 0;
        if (!pointer_) return fail(reason, "unknown pointer size");
        if (b_[8] != 'v' && b_[8] != 'V') return fail(reason, "unknown byte order");
        big_ = b_[8] == 'V';
        version_ = std::atoi(b_.substr(9, 3).c_str());
        size_t at = 12;
        while (at + 16 + pointer_ <= b_.size()) {
            Block blk;
            blk.code = b_.substr(at, 4);
            blk.size = u32(at + 4);
            blk.address = pointer_ == 8 ? u64(at + 8) : u32(at + 8);
            blk.sdna = u32(at + 8 + pointer_);
            blk.count = u32(at + 12 + pointer_);
            blk.data = at + 16 + pointer_;
            if (blk.code == "ENDB") break;
            if (blk.data + blk.size > b_.size()) return fail(reason, "truncated file block");
            if (blk.code == "DNA1" && !readDna(blk.data, blk.size)) return fail(reason, "bad DNA");
            blocks_.push_back(blk);
            at = blk.data + blk.size;
        }
        if (structs_.empty()) return fail(reason, "no DNA block");
        return true;
    }

    int version() const { return version_; }

    std::vector<BlendLamp> lamps() const {
        std::map<uint64_t, const Block*> byAddress;
        for (const Block& blk : blocks_) byAddress[blk.address] = &blk;
        std::vector<BlendLamp> out;
        for (const Block& obj : blocks_) {
            if (structName(obj.sdna) != "Object" || obj.code == "DATA") continue;
            auto data = pointerField(obj, "data");
            auto it = data ? byAddress.find(*data) : byAddress.end();
            if (it == byAddress.end()) continue;
            const Block& lamp = *it->second;
            std::string type = structName(lamp.sdna);
            if (type != "Lamp" && type != "Light") continue;
            BlendLamp l;
            l.object = idName(obj);
            l.type = intField(lamp, "type").value_or(0);
            l.mode = intField(lamp, "mode").value_or(0);
            l.falloffType = intField(lamp, "falloff_type").value_or(-1);
            l.r = floatField(lamp, "r").value_or(1), l.g = floatField(lamp, "g").value_or(1);
            l.b = floatField(lamp, "b").value_or(1);
            l.energy = floatField(lamp, "energy").value_or(1);
            l.dist = floatField(lamp, "dist").value_or(25);
            l.att1 = floatField(lamp, "att1").value_or(0);
            l.att2 = floatField(lamp, "att2").value_or(1);
            l.gamma = floatField(lamp, "k").value_or(1);
            l.spotSize = floatField(lamp, "spotsize").value_or(0);
            l.spotBlend = floatField(lamp, "spotblend").value_or(0);
            l.areaSize = floatField(lamp, "area_size").value_or(0);
            l.areaSizeY = floatField(lamp, "area_sizey").value_or(0);
            l.areaShape = intField(lamp, "area_shape").value_or(0);
            out.push_back(l);
        }
        return out;
    }

  private:
    struct Block {
        std::string code;
        uint32_t size = 0, sdna = 0, count = 0;
        uint64_t address = 0;
        size_t data = 0;
    };

    static bool fail(std::string& reason, const char* what) {
        reason = what;
        return false;
    }
    uint16_t u16(size_t at) const {
        uint16_t v;
        std::memcpy(&v, b_.data() + at, 2);
        return big_ ? __builtin_bswap16(v) : v;
    }
    uint32_t u32(size_t at) const {
        uint32_t v;
        std::memcpy(&v, b_.data() + at, 4);
        return big_ ? __builtin_bswap32(v) : v;
    }
    uint64_t u64(size_t at) const {
        uint64_t v;
        std::memcpy(&v, b_.data() + at, 8);
        return big_ ? __builtin_bswap64(v) : v;
    }

    // "SDNA" "NAME" n names "TYPE" n types "TLEN" n shorts "STRC" n structs, 4-byte aligned.
    bool readDna(size_t at, size_t size) {
        size_t end = at + size;
        auto expect = [&](const char* tag) {
            at = (at + 3) & ~size_t(3);
            if (at + 8 > end || b_.compare(at, 4, tag) != 0) return false;
            at += 4;
            return true;
        };
        auto strings = [&](std::vector<std::string>& out) {
            uint32_t n = u32(at);
            at += 4;
            for (uint32_t i = 0; i < n; ++i) {
                size_t zero = b_.find('\0', at);
                if (zero == std::string::npos || zero >= end) return false;
                out.push_back(b_.substr(at, zero - at));
                at = zero + 1;
            }
            return true;
        };
        if (b_.compare(at, 4, "SDNA") != 0) return false;
        at += 4;
        if (!expect("NAME") || !strings(names_) || !expect("TYPE") || !strings(types_) ||
            !expect("TLEN"))
            return false;
        for (size_t i = 0; i < types_.size(); ++i, at += 2) {
            if (at + 2 > end) return false;
            lengths_.push_back(u16(at));
        }
        if (!expect("STRC")) return false;
        uint32_t n = u32(at);
        at += 4;
        for (uint32_t i = 0; i < n; ++i) {
            if (at + 4 > end) return false;
            uint16_t type = u16(at), count = u16(at + 2);
            at += 4;
            if (type >= types_.size() || at + 4 * size_t(count) > end) return false;
            DnaStruct s{types_[type], {}};
            for (uint16_t f = 0; f < count; ++f, at += 4) {
                uint16_t ft = u16(at), fn = u16(at + 2);
                if (ft >= types_.size() || fn >= names_.size()) return false;
                s.fields.push_back({types_[ft], names_[fn]});
            }
            structByType_[s.type] = structs_.size();
            structs_.push_back(std::move(s));
        }
        return true;
    }

    std::string structName(uint32_t sdna) const {
        return sdna < structs_.size() ? structs_[sdna].type : "";
    }

    // Bytes a field takes: pointers the file's pointer size, arrays their element count.
    size_t fieldBytes(const DnaField& f) const {
        size_t count = 1;
        for (size_t open = f.name.find('['); open != std::string::npos;
             open = f.name.find('[', open + 1))
            count *= size_t(std::max(1, std::atoi(f.name.c_str() + open + 1)));
        if (f.name[0] == '*' || f.name[0] == '(') return count * pointer_;
        for (size_t t = 0; t < types_.size(); ++t)
            if (types_[t] == f.type) return count * lengths_[t];
        return 0;
    }

    static std::string bareName(const std::string& name) {
        size_t start = name.find_first_not_of("*(");
        size_t end = name.find_first_of("[)", start);
        return name.substr(start, end == std::string::npos ? std::string::npos : end - start);
    }

    // Byte offset and field of `path` in struct sdna (a nested struct's field as "outer.inner").
    std::optional<std::pair<size_t, DnaField>> field(uint32_t sdna, const std::string& path) const {
        if (sdna >= structs_.size()) return std::nullopt;
        size_t dot = path.find('.');
        std::string head = path.substr(0, dot);
        size_t offset = 0;
        for (const DnaField& f : structs_[sdna].fields) {
            if (bareName(f.name) == head) {
                if (dot == std::string::npos) return std::make_pair(offset, f);
                auto inner = structByType_.find(f.type);
                if (f.name[0] == '*' || inner == structByType_.end()) return std::nullopt;
                auto rest = field(uint32_t(inner->second), path.substr(dot + 1));
                if (rest) rest->first += offset;
                return rest;
            }
            size_t bytes = fieldBytes(f);
            if (!bytes) return std::nullopt;
            offset += bytes;
        }
        return std::nullopt;
    }

    std::optional<float> floatField(const Block& blk, const std::string& name) const {
        auto f = field(blk.sdna, name);
        if (!f || f->first + 4 > blk.size) return std::nullopt;
        if (f->second.type == "float") return std::bit_cast<float>(u32(blk.data + f->first));
        return std::nullopt;
    }
    std::optional<int> intField(const Block& blk, const std::string& name) const {
        auto f = field(blk.sdna, name);
        if (!f) return std::nullopt;
        const std::string& t = f->second.type;
        size_t at = blk.data + f->first;
        if ((t == "short" || t == "ushort") && f->first + 2 <= blk.size)
            return t == "short" ? int(int16_t(u16(at))) : int(u16(at));
        if (t == "int" && f->first + 4 <= blk.size) return int(u32(at));
        if ((t == "char" || t == "uchar") && f->first + 1 <= blk.size) return int(uint8_t(b_[at]));
        return std::nullopt;
    }
    std::optional<uint64_t> pointerField(const Block& blk, const std::string& name) const {
        auto f = field(blk.sdna, name);
        if (!f || f->second.name[0] != '*' || f->first + pointer_ > blk.size) return std::nullopt;
        size_t at = blk.data + f->first;
        return pointer_ == 8 ? u64(at) : u32(at);
    }
    // The object's name without its two-letter ID code ("OBLamp" -> "Lamp"), as Assimp names it.
    std::string idName(const Block& blk) const {
        auto f = field(blk.sdna, "id.name");
        if (!f) return "";
        size_t at = blk.data + f->first,
               bytes = std::min<size_t>(fieldBytes(f->second), blk.size - f->first);
        std::string name(b_.data() + at, strnlen(b_.data() + at, bytes));
        return name.size() > 2 ? name.substr(2) : "";
    }

    std::string b_;
    size_t pointer_ = 8;
    bool big_ = false;
    int version_ = 0;
    std::vector<std::string> names_, types_;
    std::vector<uint16_t> lengths_;
    std::vector<DnaStruct> structs_;
    std::map<std::string, size_t> structByType_;
    std::vector<Block> blocks_;
};

}  // namespace

std::optional<BlendLamps> readBlendLamps(const std::string& path, std::string& reason) {
    gzFile in = gzopen(path.c_str(), "rb");
    if (!in) {
        reason = "cannot open";
        return std::nullopt;
    }
    std::string bytes;
    char buffer[1 << 16];
    for (int n; (n = gzread(in, buffer, sizeof buffer)) > 0;) bytes.append(buffer, size_t(n));
    gzclose(in);
    BlendReader reader(std::move(bytes));
    if (!reader.parse(reason)) return std::nullopt;
    return BlendLamps{reader.version(), reader.lamps()};
}

}  // namespace kiln
