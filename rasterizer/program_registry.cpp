// The program registry (rasterizer/include/rasterizer/program_registry.h): names ↔ program
// triples for traces, and the GLSL twins the Mesa player runs.
#include "rasterizer/program_registry.h"

#include <cxxabi.h>

#include <algorithm>
#include <cstdlib>
#include <deque>
#include <map>
#include <memory>
#include <mutex>

#include "core/error.h"

namespace rg::raster {

namespace {

// Entries are never removed, so pointers into the deque stay valid for the program's life
// (a Trace holds them).
struct Registry {
    std::mutex mutex;
    std::deque<RegisteredProgram> programs;
    std::map<std::string, const RegisteredProgram*, std::less<>> byName;
    std::map<std::type_index, const RegisteredProgram*> byKey;
    std::deque<GlslTwin> twins;
    std::map<std::string, const GlslTwin*, std::less<>> twinByName;
};

Registry& registry() {
    static Registry r;
    return r;
}

std::string demangle(const std::type_info& t) {
    int status = 0;
    std::unique_ptr<char, void (*)(void*)> s(abi::__cxa_demangle(t.name(), nullptr, nullptr, &status), std::free);
    return status == 0 && s ? std::string(s.get()) : std::string(t.name());
}

void checkName(const std::string& name) {
    const bool ok = !name.empty() && name.size() <= 255 &&
                    std::all_of(name.begin(), name.end(), [](char c) {
                        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '/' ||
                               c == '.' || c == '-';
                    });
    if (!ok)
        throw Error("program name '" + name + "': 1 to 255 characters of a-z, 0-9, '_', '/', '.', '-'");
}

}  // namespace

std::string detail::programTypeNames(const std::type_info& vp, const std::type_info& fp, const std::type_info& v) {
    return demangle(vp) + ", " + demangle(fp) + ", " + demangle(v);
}

std::string detail::programKeyName(std::type_index key) {
    int status = 0;
    std::unique_ptr<char, void (*)(void*)> s(abi::__cxa_demangle(key.name(), nullptr, nullptr, &status), std::free);
    return status == 0 && s ? std::string(s.get()) : std::string(key.name());
}

const RegisteredProgram& detail::addProgram(RegisteredProgram p) {
    checkName(p.name);
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    if (auto it = r.byName.find(p.name); it != r.byName.end()) {
        if (it->second->key == p.key) return *it->second;  // registered again: a no-op
        throw Error("program name '" + p.name + "' is already registered for " + it->second->types +
                    ", not " + p.types);
    }
    if (auto it = r.byKey.find(p.key); it != r.byKey.end())
        throw Error("the program " + p.types + " is already registered as '" + it->second->name +
                    "'; one name per program, so that a trace names it one way");
    const RegisteredProgram& added = r.programs.emplace_back(std::move(p));
    r.byName.emplace(added.name, &added);
    r.byKey.emplace(added.key, &added);
    return added;
}

const RegisteredProgram* findProgram(std::string_view name) {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    auto it = r.byName.find(name);
    return it == r.byName.end() ? nullptr : it->second;
}

const RegisteredProgram* findProgram(std::type_index key) {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    auto it = r.byKey.find(key);
    return it == r.byKey.end() ? nullptr : it->second;
}

std::vector<std::string> registeredProgramNames() {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    std::vector<std::string> names;
    for (const auto& [name, p] : r.byName) names.push_back(name);
    return names;  // std::map: sorted
}

void registerGlslTwin(const std::string& name, GlslTwin twin) {
    checkName(name);
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    if (auto it = r.twinByName.find(name); it != r.twinByName.end()) {
        if (it->second->vertexShader == twin.vertexShader && it->second->fragmentShader == twin.fragmentShader)
            return;  // registered again: a no-op
        throw Error("a different GLSL twin is already registered for program '" + name + "'");
    }
    const GlslTwin& added = r.twins.emplace_back(std::move(twin));
    r.twinByName.emplace(name, &added);
}

const GlslTwin* findGlslTwin(std::string_view name) {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    auto it = r.twinByName.find(name);
    return it == r.twinByName.end() ? nullptr : it->second;
}

}  // namespace rg::raster
