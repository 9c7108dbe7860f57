#include "architecture_check.h"

#include <fnmatch.h>

#include <algorithm>
#include <deque>
#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <sstream>

namespace kiln::arch {

namespace fs = std::filesystem;

namespace {

const std::set<std::string> kCppExtensions = {".h", ".hpp", ".hh", ".cpp", ".cc", ".cxx"};

std::string str(const fs::path& p) { return p.generic_string(); }

// tests/ and everything below it stand on the roof: they may include any floor.
bool onTheRoof(const std::string& folder) {
    return folder == "tests" || folder.rfind("tests/", 0) == 0;
}

// The "/NAME/" lines of the root .gitignore (build outputs: /build/, /build-*/, /out/).
std::vector<std::string> ignoredTopFolders(const fs::path& root) {
    std::ifstream in(root / ".gitignore");
    std::vector<std::string> patterns;
    std::regex topFolder(R"(^/([^/]+)/\s*$)");
    std::string line;
    std::smatch m;
    while (std::getline(in, line))
        if (std::regex_match(line, m, topFolder)) patterns.push_back(m[1]);
    return patterns;
}

// Files under dir (relative to root, sorted) whose extension is in exts; hidden folders, the
// ignored top folders and __pycache__ are not entered.
std::vector<fs::path> walk(const fs::path& root, const fs::path& dir,
                           const std::set<std::string>& exts) {
    std::vector<fs::path> files;
    if (!fs::is_directory(dir)) return files;
    const auto ignored = ignoredTopFolders(root);
    for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator();
         ++it) {
        const fs::path rel = fs::relative(it->path(), root);
        const std::string name = it->path().filename().string();
        if (it->is_directory()) {
            bool skip = name.empty() || name[0] == '.' || name == "__pycache__";
            if (rel.parent_path().empty())
                for (const auto& pattern : ignored)
                    skip = skip || fnmatch(pattern.c_str(), name.c_str(), 0) == 0;
            if (skip) it.disable_recursion_pending();
            continue;
        }
        if (it->is_regular_file() && exts.count(it->path().extension().string()))
            files.push_back(rel);
    }
    std::sort(files.begin(), files.end());
    return files;
}

struct Include {
    int line;
    bool quoted;
    std::string header;  // as written
};

std::vector<Include> includes(const fs::path& file) {
    std::ifstream in(file);
    static const std::regex inc(R"re(^\s*#\s*include\s*([<"])([^>"]+)[>"])re");
    std::vector<Include> out;
    std::string line;
    std::smatch m;
    for (int n = 1; std::getline(in, line); ++n)
        if (std::regex_search(line, m, inc)) out.push_back({n, m[1] == "\"", m[2]});
    return out;
}

// The repository path an include names, or "" when it names no project header: a quoted name
// without a folder is a header of the including file's own folder; a quoted path is looked up from
// the including folder, then from the root; an angle-bracket path is a project header when its
// first folder is a top folder of the root or the root holds the file it names.
std::string target(const fs::path& root, const std::string& folder, const Include& inc) {
    const fs::path header = fs::path(inc.header).lexically_normal();
    if (inc.quoted) {
        if (!header.has_parent_path()) return str(fs::path(folder) / header);
        const fs::path local = (fs::path(folder) / header).lexically_normal();
        if (fs::exists(root / local)) return str(local);
        return str(header);
    }
    const fs::path first = *header.begin();
    const bool topFolder =
        header.has_parent_path() && first.string()[0] != '.' && fs::is_directory(root / first);
    if (topFolder || fs::is_regular_file(root / header)) return str(header);
    return "";
}

std::string folderOf(const std::string& path) { return str(fs::path(path).parent_path()); }

// ---- loops: a directed graph, its strongly connected components, one shortest loop in each ----

struct Edge {
    std::string to;
    std::string file;  // where the edge is written
    int line;
    std::string what;  // "includes x.h", "imports y"
};
using Graph = std::map<std::string, std::vector<Edge>>;

std::vector<std::vector<std::string>> components(const Graph& g) {
    std::map<std::string, int> index, low;
    std::vector<std::string> stack;
    std::set<std::string> onStack;
    std::vector<std::vector<std::string>> out;
    int next = 0;
    std::function<void(const std::string&)> visit = [&](const std::string& v) {
        index[v] = low[v] = next++;
        stack.push_back(v);
        onStack.insert(v);
        auto it = g.find(v);
        if (it != g.end())
            for (const Edge& e : it->second) {
                if (!index.count(e.to)) {
                    visit(e.to);
                    low[v] = std::min(low[v], low[e.to]);
                } else if (onStack.count(e.to)) {
                    low[v] = std::min(low[v], index[e.to]);
                }
            }
        if (low[v] == index[v]) {
            std::vector<std::string> comp;
            std::string w;
            do {
                w = stack.back();
                stack.pop_back();
                onStack.erase(w);
                comp.push_back(w);
            } while (w != v);
            std::sort(comp.begin(), comp.end());
            out.push_back(comp);
        }
    };
    for (const auto& [v, _] : g)
        if (!index.count(v)) visit(v);
    std::sort(out.begin(), out.end());
    return out;
}

// The shortest loop from the component's first node back to it, as its edges in order.
std::vector<Edge> shortestLoop(const Graph& g, const std::vector<std::string>& comp) {
    const std::set<std::string> inside(comp.begin(), comp.end());
    const std::string& start = comp.front();
    std::map<std::string, std::pair<std::string, Edge>> parent;  // node -> (from, edge)
    std::deque<std::string> queue{start};
    std::set<std::string> seen{start};
    while (!queue.empty()) {
        const std::string v = queue.front();
        queue.pop_front();
        auto it = g.find(v);
        if (it == g.end()) continue;
        for (const Edge& e : it->second) {
            if (!inside.count(e.to)) continue;
            if (e.to == start) {
                std::vector<Edge> loop{e};
                for (std::string at = v; at != start; at = parent.at(at).first)
                    loop.push_back(parent.at(at).second);
                std::reverse(loop.begin(), loop.end());
                return loop;
            }
            if (seen.insert(e.to).second) {
                parent.emplace(e.to, std::make_pair(v, e));
                queue.push_back(e.to);
            }
        }
    }
    return {};
}

// One violation per loop of the graph: the shortest loop through its first member, and all members.
std::vector<Violation> loops(const Graph& g, Rule rule, const std::string& kind) {
    std::vector<Violation> out;
    for (const auto& comp : components(g)) {
        if (comp.size() < 2) continue;
        const std::vector<Edge> loop = shortestLoop(g, comp);
        std::ostringstream msg;
        msg << kind << ": ";
        for (const Edge& e : loop) msg << e.file << ":" << e.line << " " << e.what << "; ";
        msg << "the loop holds";
        for (const auto& v : comp) msg << " " << v;
        out.push_back({rule, loop.empty() ? comp.front() : loop.front().file,
                       loop.empty() ? 0 : loop.front().line, msg.str()});
    }
    return out;
}

// ---- Python imports ----

struct Import {
    int line;
    std::string module;  // the first name of the dotted path
};

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r()\\");
    if (b == std::string::npos) return "";
    const auto e = s.find_last_not_of(" \t\r()\\");
    return s.substr(b, e - b + 1);
}

// The first names of "a.b as c, d" (a, d).
std::vector<std::string> names(const std::string& list) {
    std::vector<std::string> out;
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
        item = trim(item);
        item = item.substr(0, item.find_first_of(" \t."));
        if (!item.empty()) out.push_back(item);
    }
    return out;
}

// The import statements of a Python file (those inside functions too), outside triple-quoted
// strings and comments: "import a.b, c as d" gives a and c; "from a.b import x" gives a;
// "from . import x, y" gives x and y.
std::vector<Import> pythonImports(const fs::path& file) {
    std::ifstream in(file);
    static const std::regex fromImport(R"(^\s*from\s+(\.*)([\w.]*)\s+import\s+(.*)$)");
    static const std::regex plainImport(R"(^\s*import\s+(.*)$)");
    static const std::string kDouble = "\"\"\"", kSingle = "'''";
    std::vector<Import> out;
    std::string line, quote;  // quote: the delimiter of the open triple-quoted string
    std::smatch m;
    for (int n = 1; std::getline(in, line); ++n) {
        // Cut triple-quoted strings out of the line; what is left is code.
        std::string code;
        size_t at = 0;
        while (at <= line.size()) {
            if (!quote.empty()) {
                const auto close = line.find(quote, at);
                if (close == std::string::npos) break;
                at = close + 3;
                quote.clear();
                continue;
            }
            const auto d = line.find(kDouble, at), s = line.find(kSingle, at);
            const auto open = std::min(d, s);
            code += line.substr(at, open == std::string::npos ? std::string::npos : open - at);
            if (open == std::string::npos) break;
            quote = open == d ? kDouble : kSingle;
            at = open + 3;
        }
        code = code.substr(0, code.find('#'));
        code = code.substr(0, code.find(';'));
        if (std::regex_match(code, m, fromImport)) {
            if (!m[2].str().empty()) {
                for (const auto& name : names(m[2])) out.push_back({n, name});
            } else {
                for (const auto& name : names(m[3])) out.push_back({n, name});
            }
        } else if (std::regex_match(code, m, plainImport)) {
            for (const auto& name : names(m[1])) out.push_back({n, name});
        }
    }
    return out;
}

}  // namespace

const char* ruleName(Rule rule) {
    switch (rule) {
        case Rule::NoFloorTable:
            return "no floor table";
        case Rule::UnlistedFolder:
            return "folder not in the floor table";
        case Rule::HigherFloor:
            return "include from a higher floor";
        case Rule::SiblingFolder:
            return "include from a sibling folder";
        case Rule::UnknownFolder:
            return "include from a folder that is not a floor";
        case Rule::AngleInclude:
            return "project header in angle brackets";
        case Rule::UnitLoop:
            return "include loop within a folder";
        case Rule::PythonImportLoop:
            return "tools/ Python import loop";
    }
    return "?";
}

std::string describe(const std::vector<Violation>& violations) {
    std::ostringstream out;
    for (const Violation& v : violations) {
        out << v.file;
        if (v.line > 0) out << ":" << v.line;
        out << ": [" << ruleName(v.rule) << "] " << v.message << "\n";
    }
    return out.str();
}

std::map<std::string, int> readFloors(const fs::path& root) {
    std::ifstream in(root / "docs/architecture.md");
    std::map<std::string, int> floors;
    static const std::regex row(R"(^\|\s*(\d+)\s*\|\s*`([a-z_/]+)`\s*\|)");
    std::string line;
    std::smatch m;
    while (std::getline(in, line))
        if (std::regex_search(line, m, row)) floors[m[2]] = std::stoi(m[1]);
    return floors;
}

std::vector<fs::path> cppFiles(const fs::path& root) { return walk(root, root, kCppExtensions); }

std::vector<fs::path> toolsPythonFiles(const fs::path& root) {
    return walk(root, root / "tools", {".py"});
}

std::vector<Violation> checkFloors(const fs::path& root) {
    const auto floors = readFloors(root);
    if (floors.empty())
        return {{Rule::NoFloorTable, "docs/architecture.md", 0,
                 "no floor table (rows of the form | N | `folder` |)"}};
    std::vector<Violation> out;
    std::map<std::string, std::vector<std::string>> unlisted;  // folder -> its files
    for (const fs::path& rel : cppFiles(root)) {
        const std::string file = str(rel), folder = folderOf(file);
        if (onTheRoof(folder)) continue;
        const auto own = floors.find(folder);
        if (own == floors.end()) {
            unlisted[folder].push_back(rel.filename().string());
            continue;
        }
        for (const Include& inc : includes(root / rel)) {
            const std::string header = target(root, folder, inc);
            const std::string theirFolder = folderOf(header);
            if (header.empty() || theirFolder == folder) continue;
            std::ostringstream msg;
            msg << "(floor " << own->second << ", " << folder << ") includes " << inc.header;
            if (onTheRoof(theirFolder)) {
                msg << " (the roof, " << theirFolder << ")";
                out.push_back({Rule::HigherFloor, file, inc.line, msg.str()});
                continue;
            }
            const auto theirs = floors.find(theirFolder);
            if (theirs == floors.end()) {
                msg << " from " << (theirFolder.empty() ? "the root" : theirFolder)
                    << ", which is not a floor";
                out.push_back({Rule::UnknownFolder, file, inc.line, msg.str()});
                continue;
            }
            msg << " (floor " << theirs->second << ", " << theirFolder << ")";
            if (theirs->second > own->second)
                out.push_back({Rule::HigherFloor, file, inc.line, msg.str()});
            else if (theirs->second == own->second)
                out.push_back({Rule::SiblingFolder, file, inc.line, msg.str()});
        }
    }
    for (const auto& [folder, files] : unlisted) {
        std::ostringstream msg;
        msg << "holds " << files.size() << " C++ file(s) (";
        for (size_t i = 0; i < files.size(); ++i) msg << (i ? ", " : "") << files[i];
        msg << ") but is not a floor in docs/architecture.md";
        out.push_back({Rule::UnlistedFolder, folder.empty() ? "." : folder, 0, msg.str()});
    }
    return out;
}

std::vector<Violation> checkAngleIncludes(const fs::path& root) {
    std::vector<Violation> out;
    for (const fs::path& rel : cppFiles(root)) {
        const std::string file = str(rel), folder = folderOf(file);
        for (const Include& inc : includes(root / rel))
            if (!inc.quoted && !target(root, folder, inc).empty())
                out.push_back({Rule::AngleInclude, file, inc.line,
                               "#include <" + inc.header +
                                   ">: a project header; write #include \"" + inc.header + "\""});
    }
    return out;
}

std::vector<Violation> checkUnitLoops(const fs::path& root) {
    // A unit: FOLDER/STEM, its .h and .cpp together.
    auto unitOf = [](const std::string& path) {
        return str(fs::path(path).parent_path() / fs::path(path).stem());
    };
    const auto files = cppFiles(root);
    std::set<std::string> units;
    for (const fs::path& rel : files) units.insert(unitOf(str(rel)));
    Graph g;
    for (const fs::path& rel : files) {
        const std::string file = str(rel), folder = folderOf(file), unit = unitOf(file);
        g[unit];
        for (const Include& inc : includes(root / rel)) {
            const std::string header = target(root, folder, inc);
            if (header.empty() || folderOf(header) != folder) continue;
            const std::string to = unitOf(header);
            if (to == unit || !units.count(to)) continue;
            g[unit].push_back({to, file, inc.line, "includes " + header});
        }
    }
    return loops(g, Rule::UnitLoop, "units of one folder include each other");
}

std::vector<Violation> checkPythonImports(const fs::path& root) {
    const auto files = toolsPythonFiles(root);
    std::map<std::string, std::vector<std::string>> byName;  // module name -> files
    for (const fs::path& rel : files) byName[rel.stem().string()].push_back(str(rel));
    Graph g;
    for (const fs::path& rel : files) {
        const std::string file = str(rel), folder = folderOf(file);
        g[file];
        for (const Import& imp : pythonImports(root / rel)) {
            auto it = byName.find(imp.module);
            if (it == byName.end()) continue;
            // A module of the importer's own folder first (Python looks there first), else
            // every module of that name under tools/.
            std::vector<std::string> to;
            for (const auto& f : it->second)
                if (folderOf(f) == folder) to.push_back(f);
            if (to.empty()) to = it->second;
            for (const auto& f : to)
                if (f != file) g[file].push_back({f, file, imp.line, "imports " + imp.module});
        }
    }
    return loops(g, Rule::PythonImportLoop, "tools/ modules import each other");
}

std::vector<Violation> checkAll(const fs::path& root) {
    std::vector<Violation> out;
    for (auto check : {checkFloors, checkAngleIncludes, checkUnitLoops, checkPythonImports}) {
        auto found = check(root);
        out.insert(out.end(), found.begin(), found.end());
    }
    return out;
}

}  // namespace kiln::arch
