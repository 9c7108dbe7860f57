// The kiln Python module (import kiln; docs/python.md): a scene loaded and built once, rendered
// through RenderJob as kiln render renders it, images as numpy arrays over kiln's buffers. Its
// keywords are kiln render's options by their long names (spp=, max_depth=, look_at=), turned
// into kiln render's arguments and parsed by its own parser, so the same values give the same
// image and the same messages. Renders run with the GIL released; the progress callback, a
// cancel event and Ctrl-C are served by the calling thread.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <set>
#include <string_view>
#include <thread>

#include "color/color_config.h"
#include "python/session.h"
#include "renderer/core/log.h"
#include "scene/scene_error.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace kiln::python {
namespace {

// kiln render's option groups that kiln.RenderOptions takes, and the one kiln.load takes.
const std::set<std::string> kRenderGroups = {"Image",  "Sampling", "Transport",
                                             "Output", "Camera",   "Accelerator"};
const std::set<std::string> kLoadGroups = {"Scene"};
// Options in those groups that name the command line's output files: image.write() names them.
const std::set<std::string> kNotKeywords = {"output", "accumulate", "file"};

using Declared = ArgParser::Declared;

const std::vector<Declared>& renderDeclarations() {
    static const std::vector<Declared> list = [] {
        RenderCommand c;
        return renderParser(c).declared();
    }();
    return list;
}

std::string keywordOf(const std::string& longName) {
    std::string k = longName;
    std::replace(k.begin(), k.end(), '-', '_');
    return k;
}

// The declarations of these groups: keyword name -> option.
std::map<std::string, const Declared*> keywordsOf(const std::vector<Declared>& declared,
                                                  const std::set<std::string>& groups) {
    std::map<std::string, const Declared*> out;
    for (const Declared& d : declared)
        if (groups.count(d.group) && !kNotKeywords.count(d.longName))
            out[keywordOf(d.longName)] = &d;
    return out;
}

const std::map<std::string, const Declared*>& renderKeywords() {
    static const auto map = keywordsOf(renderDeclarations(), kRenderGroups);
    return map;
}
const std::map<std::string, const Declared*>& loadKeywords() {
    static const auto map = keywordsOf(renderDeclarations(), kLoadGroups);
    return map;
}

// What Python says for an unknown keyword, with the nearest known names.
[[noreturn]] void unexpectedKeyword(const std::string& function, const std::string& keyword,
                                    const std::map<std::string, const Declared*>& known) {
    std::vector<std::string> names;
    for (const auto& [name, d] : known) names.push_back(name);
    py::list close = py::module_::import("difflib").attr("get_close_matches")(keyword, names);
    std::string hint;
    for (const py::handle& n : close) hint += (hint.empty() ? "" : ", ") + n.cast<std::string>();
    throw py::type_error(function + "() got an unexpected keyword argument '" + keyword + "'" +
                         (hint.empty() ? "" : " (did you mean " + hint + "?)"));
}

// True and False, numpy's booleans among them (np.bool_: numpy.bool_ before numpy 2).
bool isBool(const py::handle& v) {
    const std::string_view type = Py_TYPE(v.ptr())->tp_name;
    return PyBool_Check(v.ptr()) || type == "numpy.bool_" || type == "numpy.bool";
}

// A path or name as the C++ side takes it: the bytes os.fsencode gives (a name that is not UTF-8,
// as os.fsdecode made it, reaches the file), refused with a NUL in it, where the C side would
// end it and open another file.
std::string fsText(const py::handle& v, const std::string& what) {
    const std::string bytes = py::module_::import("os").attr("fsencode")(v).cast<py::bytes>();
    if (bytes.find('\0') != std::string::npos)
        throw py::value_error(what + ": embedded null character in " +
                              py::repr(v).cast<std::string>());
    return bytes;
}

// A path or message from the C++ side for Python: os.fsdecode, which gives back the str a
// non-UTF-8 name came in as.
py::str fsStr(const std::string& bytes) {
    return py::module_::import("os").attr("fsdecode")(py::bytes(bytes));
}

// One value as kiln render's command line would spell it: numbers in their shortest exact form.
std::string argumentText(const py::handle& v, const std::string& keyword) {
    PyObject* p = v.ptr();
    if (isBool(v)) throw py::type_error(keyword + " takes a value, not True or False");
    if (py::isinstance<py::str>(v) || py::isinstance<py::bytes>(v)) return fsText(v, keyword);
    if (PyLong_Check(p) || PyIndex_Check(p))
        return py::str(py::int_(py::reinterpret_borrow<py::object>(v))).cast<std::string>();
    if (PyFloat_Check(p) || py::hasattr(v, "__float__"))
        return py::repr(py::float_(py::reinterpret_borrow<py::object>(v))).cast<std::string>();
    if (py::hasattr(v, "__fspath__")) return fsText(v, keyword);
    throw py::type_error(keyword + " takes a number or a name, got " +
                         py::repr(v).cast<std::string>());
}

bool isSequence(const py::handle& v) {
    return !py::isinstance<py::str>(v) && !py::isinstance<py::bytes>(v) &&
           PySequence_Check(v.ptr());
}

// keyword=value as kiln render's arguments ("--long-name" and its values).
void appendArguments(std::vector<std::string>& args, const std::string& keyword,
                     const py::handle& value, const Declared& d) {
    if (value.is_none()) return;  // the default
    const std::string flag = "--" + d.longName;
    if (d.nargs == 0) {
        if (!isBool(value))
            throw py::type_error(keyword + " takes True or False, got " +
                                 py::repr(value).cast<std::string>());
        if (PyObject_IsTrue(value.ptr()) == 1) args.push_back(flag);
        return;
    }
    if (d.nargs == 1) {
        // threads=0: all cores, as RenderSettings says (the command line leaves -t out).
        // Compared as Python ints: threads=2**70 is refused by the option's range, not by a cast.
        if (d.longName == "threads" && !isBool(value) && PyIndex_Check(value.ptr()) &&
            py::int_(py::reinterpret_borrow<py::object>(value)).equal(py::int_(0)))
            return;
        std::string text;
        if (isSequence(value)) {  // aovs=["direct", "N"]: the command line's comma list
            for (const py::handle& item : value)
                text += (text.empty() ? "" : ",") + argumentText(item, keyword);
        } else {
            text = argumentText(value, keyword);
        }
        args.insert(args.end(), {flag, text});
        return;
    }
    if (!isSequence(value) || size_t(py::len(value)) != size_t(d.nargs))
        throw py::type_error(keyword + " takes " + std::to_string(d.nargs) + " values (" +
                             d.metavar + "), got " + py::repr(value).cast<std::string>());
    args.push_back(flag);
    for (const py::handle& item : value) args.push_back(argumentText(item, keyword));
}

// Keyword arguments as kiln render's arguments, in the order given.
std::vector<std::string> argumentsOf(const py::dict& kwargs, const std::string& function,
                                     const std::map<std::string, const Declared*>& known) {
    std::vector<std::string> args;
    for (const auto& [k, v] : kwargs) {
        if (!py::isinstance<py::str>(k))
            throw py::type_error(function + "() takes options by name (str), got the key " +
                                 py::repr(k).cast<std::string>());
        std::string key = k.cast<std::string>();
        auto found = known.find(key == "aovs" ? "aov" : key);
        if (found == known.end()) unexpectedKeyword(function, key, known);
        appendArguments(args, key, v, *found->second);
    }
    return args;
}

// A new dict with the same items (py::dict(d) is d itself).
py::dict copied(const py::handle& d) {
    PyObject* copy = PyDict_Copy(d.ptr());
    if (!copy) throw py::error_already_set();
    return py::reinterpret_steal<py::dict>(copy);
}

// kiln.RenderOptions: the keywords as given and the arguments they make.
struct RenderOptions {
    py::dict given;
    std::vector<std::string> args;
};

// Checks every value now, so a bad one fails where it is given, with kiln render's message.
RenderOptions makeOptions(const py::dict& kwargs) {
    RenderOptions o;
    py::dict rest;
    for (const auto& [k, v] : kwargs) {
        if (v.is_none()) continue;
        // A list given is kept as a tuple: changing the caller's list later changes nothing.
        o.given[k] = py::isinstance<py::list>(v) ? py::tuple(py::reinterpret_borrow<py::object>(v))
                                                 : py::reinterpret_borrow<py::object>(v);
        rest[k] = v;
    }
    o.args = argumentsOf(rest, "RenderOptions", renderKeywords());
    RenderCommand c = parseRenderArguments(o.args);
    renderJobOptions(c);
    checkColour(c);
    return o;
}

py::object jsonLoads(const std::string& text) {
    return py::module_::import("json").attr("loads")(text);
}

// kiln.Scene.
struct SceneHandle {
    std::shared_ptr<LoadedScene> scene;
};

// kiln.Image: the render's film and what it says, the layers filled on first use.
struct ImageData {
    LoadedScene::Result result;
    std::vector<std::string> args;  // kiln render's arguments after the scene path
    std::once_flag filledOnce, denoisedOnce;
    FilledLayers filled;
    DenoisedFrame denoised;
    // The frame denoised once for both layers() and write(); null without --denoise. Call
    // without the GIL.
    const DenoisedFrame* denoisedFrame() {
        if (!result.command.denoise || !result.film.hasHalves()) return nullptr;
        std::call_once(denoisedOnce, [this] {
            denoised = denoiseFrame(result.film, result.command.job.job.settings.threads);
        });
        return &denoised;
    }
    const FilledLayers& layers() {
        py::gil_scoped_release release;
        std::call_once(filledOnce, [this] { filled = fillLayers(result.film, denoisedFrame()); });
        return filled;
    }
};

// A read-only numpy view of memory ImageData owns; the view keeps the image alive.
template <class T>
py::array view(const py::object& owner, const T* data, std::vector<py::ssize_t> shape) {
    py::array a(py::dtype::of<T>(), shape, {}, data, owner);
    a.attr("setflags")("write"_a = false);
    return a;
}

py::array layerView(const py::object& self, const std::string& name) {
    ImageData& d = self.cast<ImageData&>();
    const FilledLayers& f = d.layers();
    for (size_t l = 0; l < f.layers.size(); ++l)
        if (f.layers[l].name == name)
            return view(self, f.values.data() + f.offsets[l],
                        {d.result.film.height(), d.result.film.width(),
                         py::ssize_t(f.layers[l].channels.size())});
    std::string known;
    for (const ExrLayer& layer : f.layers)
        if (!layer.name.empty()) known += (known.empty() ? "" : ", ") + layer.name;
    throw py::key_error("no AOV '" + name + "' in this image (it has: " + known +
                        "; RenderOptions(aovs=...) asks for more)");
}

py::object headerValue(const ExrAttribute& v) {
    if (auto* i = std::get_if<int>(&v)) return py::int_(*i);
    if (auto* d = std::get_if<double>(&v)) return py::float_(*d);
    if (auto* s = std::get_if<std::string>(&v)) return py::str(*s);
    py::tuple t(std::get<std::vector<float>>(v).size());
    size_t i = 0;
    for (float f : std::get<std::vector<float>>(v)) t[i++] = py::float_(f);
    return t;
}

// Tiles reported by the workers, served one by one on the calling thread.
struct ProgressChannel {
    std::mutex mutex;
    std::condition_variable cv;
    uint64_t posted = 0, served = 0, done = 0, total = 0;
    bool finished = false;
};

// A Python truth value; an exception raised by __bool__ propagates.
bool truthy(const py::handle& v) {
    const int truth = PyObject_IsTrue(v.ptr());
    if (truth < 0) throw py::error_already_set();
    return truth == 1;
}

// A progress callback's answer: None (or nothing returned) goes on; any false value stops,
// numpy's False and 0 as well as False.
bool stops(const py::handle& answer) { return !answer.is_none() && !truthy(answer); }

// Between the Python thread's checks: how long Ctrl-C or a cancel event may wait.
constexpr auto kPollInterval = std::chrono::milliseconds(50);

py::object render(const SceneHandle& handle, const py::object& options, const py::object& progress,
                  const py::object& cancel, const py::kwargs& overrides) {
    py::dict merged;
    if (py::isinstance<RenderOptions>(options))
        merged = copied(options.cast<const RenderOptions&>().given);
    else if (py::isinstance<py::dict>(options))
        merged = copied(options);
    else if (!options.is_none())
        throw py::type_error(
            "render() takes a kiln.RenderOptions (or a dict of its keywords), got " +
            py::repr(options).cast<std::string>());
    for (const auto& [k, v] : overrides) merged[k] = v;
    if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
        throw py::type_error("render() progress takes a callable progress(done, total), got " +
                             py::repr(progress).cast<std::string>());
    if (!cancel.is_none() && !py::hasattr(cancel, "is_set"))
        throw py::type_error(
            "render() cancel takes a threading.Event (anything with is_set()), "
            "got " +
            py::repr(cancel).cast<std::string>());
    RenderOptions o = makeOptions(merged);
    LoadedScene& scene = *handle.scene;
    std::vector<std::string> args = scene.loadArguments();
    args.insert(args.end(), o.args.begin(), o.args.end());
    RenderCommand command = parseRenderArguments(args);

    LoadedScene::Caller caller(scene);
    std::atomic<bool> stop{false};
    ProgressChannel channel;
    RenderControl control;
    control.cancel = &stop;
    if (!progress.is_none())
        control.tileDone = [&](uint64_t done, uint64_t total) {
            // Each tile waits until the callback has seen it: a False answer stops the render
            // before the worker starts another tile.
            std::unique_lock lock(channel.mutex);
            if (stop.load()) return;
            channel.done = std::max(channel.done, done), channel.total = total;
            const uint64_t mine = ++channel.posted;
            channel.cv.notify_all();
            channel.cv.wait(lock, [&] { return channel.served >= mine; });
        };
    std::optional<LoadedScene::Result> result;
    std::exception_ptr failure;
    std::optional<py::error_already_set> pythonError;  // touched only with the GIL held
    {
        py::gil_scoped_release release;
        std::thread worker([&] {
            try {
                result.emplace(scene.render(std::move(command), control));
            } catch (...) {
                failure = std::current_exception();
            }
            std::lock_guard lock(channel.mutex);
            channel.finished = true;
            channel.cv.notify_all();
        });
        for (;;) {
            std::unique_lock lock(channel.mutex);
            channel.cv.wait_for(lock, kPollInterval, [&] {
                return channel.finished || channel.posted > channel.served;
            });
            if (channel.finished) break;
            const uint64_t upTo = channel.posted, done = channel.done, total = channel.total;
            const bool report = upTo > channel.served;
            lock.unlock();
            {
                py::gil_scoped_acquire gil;
                try {
                    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                    if (!cancel.is_none() && truthy(cancel.attr("is_set")())) stop = true;
                    if (report && !stop && stops(progress(done, total))) stop = true;
                } catch (py::error_already_set& e) {
                    stop = true;
                    if (!pythonError) pythonError.emplace(std::move(e));
                }
            }
            lock.lock();
            channel.served = upTo;
            channel.cv.notify_all();
        }
        worker.join();
    }
    if (failure) std::rethrow_exception(failure);
    auto image = std::make_shared<ImageData>();
    image->result = std::move(*result);
    image->args = o.args;
    py::object imageObject = py::cast(image);
    if (pythonError) {
        // KeyboardInterrupt (or the callback's own exception) after the render stopped at a
        // pixel: the image so far rides along as its .image.
        py::setattr(pythonError->value(), "image", imageObject);
        throw std::move(*pythonError);
    }
    return imageObject;
}

py::object crosscheck(const SceneHandle& handle, const py::dict& kwargs) {
    int rays = 1000000, seed = 1;
    AcceleratorChoice choice;
    ArgParser parser("crosscheck", "SCENE");
    parser.intOption("rays", "", "total rays", rays, 4, 1 << 30);
    parser.intOption("seed", "", "ray seed", seed, 0, 1 << 30);
    choice.addOptions(parser, false);
    std::map<std::string, const Declared*> known;
    for (const Declared& d : parser.declared()) known[keywordOf(d.longName)] = &d;
    parser.parse(argumentsOf(kwargs, "crosscheck", known));
    LoadedScene::Caller caller(*handle.scene);
    Json report;
    {
        py::gil_scoped_release release;
        report = handle.scene->crosscheck(choice, size_t(rays) / 4, uint64_t(seed));
    }
    return jsonLoads(jsonText(report));
}

constexpr const char* kRenderDoc =
    "Renders the scene through kiln's RenderJob with the options (keywords given here override "
    "them), the GIL released. progress(done, total) is called on this thread after each tile "
    "(samples); returning False (any false value but None) stops the render within the tile and "
    "returns the samples so far "
    "(image.interrupted). cancel: a threading.Event; set from another thread, it stops the "
    "render likewise. Ctrl-C raises KeyboardInterrupt once the render has stopped, the image so "
    "far as its .image.";

// An exception whose message may name a file that is not UTF-8: decoded as os.fsdecode would
// (PyErr_SetString would fail on it, and raise a UnicodeDecodeError in its place).
void setError(PyObject* type, const char* message) {
    PyObject* text = PyUnicode_DecodeFSDefault(message);
    if (!text) return;  // the decoding's own error stands
    PyErr_SetObject(type, text);
    Py_DECREF(text);
}

// Set by the module's initialisation: kiln.SceneWarning.
py::handle sceneWarning;

std::string optionsDoc(const std::map<std::string, const Declared*>& keywords) {
    std::string doc;
    for (const auto& [name, d] : keywords)
        doc += "    " + name + (d->metavar.empty() ? "=True" : "=" + d->metavar) + "\n        " +
               d->help + " (--" + d->longName + ")\n";
    return doc;
}

}  // namespace
}  // namespace kiln::python

using namespace kiln::python;

PYBIND11_MODULE(_kiln, m) {
    m.doc() = "kiln, a batch path tracer: load a scene once, render it through kiln's RenderJob.";
    m.attr("__version__") = KILN_VERSION;
    // numpy's C API set up now, on the importing thread: pybind11 does it on first use, in a
    // static whose initialisation imports numpy, which releases the GIL; two threads making their
    // first views at once deadlocked there.
    py::module_::import("numpy");
    (void)py::dtype::of<float>();

    // Never destroyed: Python may be gone by the time static destructors run.
    static auto* sceneError = new py::exception<kiln::SceneError>(m, "SceneError");
    sceneError->attr("__doc__") =
        "Bad input: the scene file, its data or an environment map, with kiln's one-line message.";
    sceneError->attr("__module__") = "kiln";
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const kiln::UsageError& e) {
            setError(PyExc_ValueError, e.what());
        } catch (const kiln::SceneError& e) {
            setError(sceneError->ptr(), e.what());
        }
    });
    m.attr("SceneWarning") =
        py::module_::import("builtins")
            .attr("type")("SceneWarning", py::make_tuple(py::handle(PyExc_UserWarning)),
                          py::dict("__module__"_a = "kiln"));
    sceneWarning = m.attr("SceneWarning");

    m.def("_set_bundled_config", &kiln::setBundledColorConfig);
    m.def(
        "set_log_level",
        [](const std::string& level) {
            auto parsed = kiln::parseEnum<kiln::LogLevel>(level);
            if (!parsed)
                throw py::value_error("log level takes " + kiln::enumChoices<kiln::LogLevel>() +
                                      ", got '" + level + "'");
            kiln::setLogLevel(*parsed);
        },
        "level"_a,
        "The least important messages kiln writes to stderr: error, warning, info, debug.");

    static const std::string renderOptionsDoc =
        "Every kiln render option by name (its long name, '-' as '_'), checked now with kiln "
        "render's messages (ValueError):\n\n" +
        optionsDoc(renderKeywords()) +
        "    aovs=LIST\n        the same as aov: a list, or names separated by commas\n";
    static const std::string loadDoc =
        "Loads a scene file with kiln's importers (kiln.SceneError on "
        "bad input). Options: kiln render's Scene group:\n\n" +
        optionsDoc(loadKeywords());
    py::class_<RenderOptions>(m, "RenderOptions", renderOptionsDoc.c_str())
        .def(py::init([](const py::kwargs& kwargs) { return makeOptions(kwargs); }))
        .def_property_readonly(
            "options", [](const RenderOptions& o) { return copied(o.given); },
            "The keywords given (a copy).")
        .def_property_readonly(
            "args", [](const RenderOptions& o) { return o.args; },
            "The same options as kiln render's arguments.")
        .def(
            "replace",
            [](const RenderOptions& o, const py::kwargs& kwargs) {
                py::dict merged = copied(o.given);
                for (const auto& [k, v] : kwargs) merged[k] = v;
                return makeOptions(merged);
            },
            "A copy with these keywords changed (None: back to the default).")
        .def_static(
            "names",
            [] {
                py::dict names;
                for (const auto& [name, d] : renderKeywords()) names[py::str(name)] = d->help;
                return names;
            },
            "Every keyword RenderOptions takes, with its help line.")
        .def("__repr__", [](const RenderOptions& o) {
            std::string text;
            for (const auto& [k, v] : o.given)
                text += (text.empty() ? "" : ", ") + k.cast<std::string>() + "=" +
                        py::repr(v).cast<std::string>();
            return "kiln.RenderOptions(" + text + ")";
        });

    py::class_<SceneHandle>(m, "Scene",
                            "A loaded scene (kiln.load); render it any number of times.")
        .def_property_readonly("path", [](const SceneHandle& s) { return fsStr(s.scene->path()); })
        .def_property_readonly(
            "load_args", [](const SceneHandle& s) { return s.scene->loadArguments(); },
            "The load keywords as kiln render's arguments.")
        .def_property_readonly("warnings",
                               [](const SceneHandle& s) { return s.scene->scene().warnings; })
        .def_property_readonly("load_seconds",
                               [](const SceneHandle& s) { return s.scene->scene().loadSeconds; })
        .def(
            "info", [](const SceneHandle& s) { return jsonLoads(s.scene->infoJson()); },
            "The facts of `kiln info --json` (docs/info-json.md) as a dict.")
        .def_property_readonly(
            "accelerators",
            [](const SceneHandle& s) {
                py::list out;
                for (const kiln::AcceleratorStats& a : s.scene->accelerators())
                    out.append(py::dict("description"_a = a.description,
                                        "build_seconds"_a = a.buildSeconds,
                                        "memory_bytes"_a = a.memoryBytes));
                return out;
            },
            "The accelerators built for this scene so far (each is built once, on first use).")
        .def("__repr__", [](const SceneHandle& s) {
            return "<kiln.Scene " + py::repr(fsStr(s.scene->path())).cast<std::string>() + ">";
        });

    m.def(
        "load",
        [](const py::object& path, const py::kwargs& kwargs) {
            const std::string file = fsText(path, "path");
            std::vector<std::string> args = argumentsOf(kwargs, "load", loadKeywords());
            std::shared_ptr<LoadedScene> scene;
            {
                py::gil_scoped_release release;
                scene = std::make_shared<LoadedScene>(file, args);
            }
            py::object warn = py::module_::import("warnings").attr("warn");
            for (const std::string& w : scene->scene().warnings)
                warn(fsStr(file + ": " + w), sceneWarning, 2);
            return SceneHandle{scene};
        },
        "path"_a, loadDoc.c_str());

    py::class_<ImageData, std::shared_ptr<ImageData>>(
        m, "Image", "A render: numpy views of its layers, its EXR header, write().")
        .def_property_readonly(
            "beauty", [](const py::object& self) { return layerView(self, ""); },
            "float32 (H, W, 4): scene-linear R, G, B and alpha (colour premultiplied), as the "
            "EXR's R, G, B, A.")
        .def(
            "aov",
            [](const py::object& self, const std::string& name) { return layerView(self, name); },
            "name"_a, "float32 (H, W, C): the EXR layer NAME ('direct', 'N', 'Z', 'samples', ...).")
        .def_property_readonly(
            "aovs",
            [](const py::object& self) {
                py::list names;
                for (const kiln::ExrLayer& l : self.cast<ImageData&>().layers().layers)
                    if (!l.name.empty()) names.append(l.name);
                return names;
            },
            "The AOV layers this image holds, in the EXR's order.")
        .def_property_readonly(
            "channels",
            [](const py::object& self) {
                py::dict out;
                for (const kiln::ExrLayer& l : self.cast<ImageData&>().layers().layers)
                    out[py::str(l.name)] = l.channels;
                return out;
            },
            "Each layer's channel names ('' is the beauty).")
        .def_property_readonly(
            "samples",
            [](const py::object& self) {
                const kiln::Film& film = self.cast<ImageData&>().result.film;
                return view(self, film.sampleCounts(), {film.height(), film.width()});
            },
            "uint32 (H, W): the samples each pixel holds (a view of the film's counts).")
        .def_property_readonly(
            "metadata",
            [](const py::object& self) {
                ImageData& d = self.cast<ImageData&>();
                py::dict out;
                for (const auto& [key, value] :
                     kiln::exrHeader(d.result.film, d.result.metadata, d.result.command.exr))
                    if (key.rfind("oiio:", 0) != 0)  // OpenImageIO's hints, not in the file
                        out[py::str(key)] = headerValue(value);
                return out;
            },
            "The EXR header's attributes as write() writes them.")
        .def_property_readonly(
            "interrupted",
            [](const py::object& self) { return self.cast<ImageData&>().result.stats.interrupted; })
        .def_property_readonly(
            "stats",
            [](const py::object& self) {
                const kiln::RenderStats& s = self.cast<ImageData&>().result.stats;
                return py::dict("seconds"_a = s.seconds, "rays"_a = s.rays, "samples"_a = s.samples,
                                "nonfinite_samples"_a = s.nonFiniteSamples,
                                "interrupted"_a = s.interrupted, "complete"_a = s.complete);
            })
        .def("__repr__",
             [](const py::object& self) {
                 const ImageData& d = self.cast<ImageData&>();
                 const kiln::Film& film = d.result.film;
                 const auto& meta = d.result.metadata;
                 return "<kiln.Image " + std::to_string(film.width()) + "x" +
                        std::to_string(film.height()) + ", " + meta.at("spp") + " spp" +
                        (d.result.stats.interrupted ? " (interrupted)" : "") + ", AOVs " +
                        meta.at("aovs") + ">";
             })
        .def_property_readonly(
            "args", [](const py::object& self) { return self.cast<ImageData&>().args; },
            "The render options as kiln render's arguments (after the scene's load arguments).")
        .def(
            "write",
            [](const py::object& self, const py::object& out) {
                static std::mutex writing;  // one OCIO/OIIO set-up at a time
                ImageData& d = self.cast<ImageData&>();
                const std::string base = fsText(out, "out");
                kiln::OutputPaths paths;
                std::string heat;
                {
                    py::gil_scoped_release release;
                    std::lock_guard lock(writing);
                    paths = writeImage(d.result, base, heat, d.denoisedFrame());
                }
                py::dict written("exr"_a = fsStr(paths.exr), "preview"_a = fsStr(paths.preview));
                if (!heat.empty()) written["heatmap"] = fsStr(heat);
                return written;
            },
            "out"_a,
            "Writes OUT.exr and OUT.png (and OUT.samples.png with adaptive sampling or heatmap) "
            "exactly as `kiln render -o OUT`; returns the paths.");

    m.def("render", &render, "scene"_a, "options"_a = py::none(), py::kw_only(),
          "progress"_a = py::none(), "cancel"_a = py::none(), kRenderDoc);
    m.def(
        "crosscheck",
        [](const SceneHandle& s, const py::kwargs& kwargs) { return crosscheck(s, kwargs); },
        "scene"_a,
        "Traces the same rays through Embree and the reference BVH (kiln crosscheck --json) "
        "and returns the classification: keywords rays (default 1000000), seed (default 1) and "
        "the accelerator options.");
}
