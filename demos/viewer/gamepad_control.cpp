#include "gamepad_control.h"

#include <hidapi/hidapi.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

namespace rg::viewer {

std::vector<Action> padActions(const pad::PadState& now, const pad::PadState& before,
                               const PadBindings& b) {
    std::vector<Action> out;
    float lx = now.lx, ly = now.ly, rx = now.rx, ry = now.ry;
    pad::shapeStick(lx, ly, b.shape);
    pad::shapeStick(rx, ry, b.shape);
    if (lx != 0 || ly != 0) {
        Action a;
        a.kind = Action::Kind::Orbit;
        a.x = lx * b.orbitDegreesPerFrame;
        a.y = ly * b.orbitDegreesPerFrame;
        out.push_back(a);
    }
    if (ry != 0) {
        Action a;
        a.kind = Action::Kind::Dolly;
        a.x = std::exp(-ry * b.dollyPerFrame);
        out.push_back(a);
    }
    if (rx != 0) {
        Action a;
        a.kind = Action::Kind::Raise;
        a.x = rx * b.raisePerFrame;
        out.push_back(a);
    }
    auto pressed = [&](uint32_t button) { return (now.buttons & button) && !(before.buttons & button); };
    if (pressed(pad::L1) || pressed(pad::R1)) {
        Action a;
        a.kind = Action::Kind::Step;
        a.value = pressed(pad::R1) ? 1 : -1;
        out.push_back(a);
    }
    if (pressed(pad::North)) out.push_back(Action{Action::Kind::Reset, 0, 0, 0, {}});
    if (pressed(pad::East)) out.push_back(Action{Action::Kind::Nearest, 0, 0, 0, {}});
    if (pressed(pad::South)) out.push_back(Action{Action::Kind::Screenshot, 0, 0, 0, {}});
    return out;
}

int padNudge(const pad::PadState& now, const pad::PadState& before) {
    if (now.hat == before.hat) return 0;
    return now.hat == 2 ? 1 : now.hat == 6 ? -1 : 0;
}

struct GamepadManager::Impl {
    bool initialised = false;
    hid_device* device = nullptr;
    pad::PadKind kind = pad::PadKind::Generic;
    pad::HidDescriptor descriptor;
    std::optional<pad::PadState> state;
};

GamepadManager::GamepadManager() : impl_(std::make_unique<Impl>()) {
    impl_->initialised = hid_init() == 0;
    if (!impl_->initialised) status_ = "hidapi failed to initialise: no gamepad";
}

GamepadManager::~GamepadManager() {
    close();
    if (impl_->initialised) hid_exit();
}

void GamepadManager::close() {
    if (impl_->device) hid_close(impl_->device);
    impl_->device = nullptr;
    impl_->state.reset();
}

namespace {

// hidapi 0.13 has no descriptor query; the hidraw backend's paths are /dev/hidrawN, whose
// descriptor sysfs exposes.
std::vector<uint8_t> reportDescriptorOf(const char* path) {
    std::string p = path ? path : "";
    auto slash = p.rfind('/');
    std::string node = slash == std::string::npos ? p : p.substr(slash + 1);
    std::ifstream f("/sys/class/hidraw/" + node + "/device/report_descriptor", std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

}  // namespace

void GamepadManager::scan() {
    if (!impl_->initialised) return;
    hid_device_info* list = hid_enumerate(0, 0);
    for (hid_device_info* d = list; d; d = d->next) {
        auto known = pad::knownPad(d->vendor_id, d->product_id);
        const bool gamepadUsage = d->usage_page == 0x01 && (d->usage == 0x04 || d->usage == 0x05);
        if (!known && !gamepadUsage) continue;
        hid_device* dev = hid_open_path(d->path);
        if (!dev) {
            messages_.push_back(std::string("gamepad: cannot open ") + d->path +
                                " (permissions of /dev/hidraw*?)");
            continue;
        }
        hid_set_nonblocking(dev, 1);
        impl_->device = dev;
        impl_->kind = known.value_or(pad::PadKind::Generic);
        impl_->descriptor = pad::parseHidDescriptor(reportDescriptorOf(d->path));
        const char* bus = d->bus_type == HID_API_BUS_BLUETOOTH ? "Bluetooth" : "USB";
        if (impl_->kind == pad::PadKind::SwitchPro && d->bus_type == HID_API_BUS_USB) {
            // Over USB the Pro Controller reports only after the handshake (0x80 0x02)
            // and the switch to HID-only talk without timeout (0x80 0x04), per the public
            // reverse-engineering notes. Untested here without the hardware.
            const uint8_t handshake[2] = {0x80, 0x02}, hidOnly[2] = {0x80, 0x04};
            hid_write(dev, handshake, sizeof handshake);
            hid_write(dev, hidOnly, sizeof hidOnly);
        }
        status_ = std::string(pad::padKindName(impl_->kind)) + " (" + bus + ", " + d->path + ")";
        messages_.push_back("gamepad: connected " + status_);
        toldNone_ = false;
        break;
    }
    hid_free_enumeration(list);
    if (!impl_->device && !toldNone_) {
        messages_.push_back("gamepad: none found (hidapi); keyboard and mouse only, plug one in any time");
        toldNone_ = true;
        status_ = "no gamepad";
    }
}

std::optional<pad::PadState> GamepadManager::poll() {
    if (!impl_->device) {
        auto now = std::chrono::steady_clock::now();
        if (now < nextScan_) return std::nullopt;
        nextScan_ = now + std::chrono::seconds(2);
        scan();
        if (!impl_->device) return std::nullopt;
    }
    uint8_t buf[256];
    for (int n = 0; n < 64; ++n) {  // drain, bounded
        int got = hid_read_timeout(impl_->device, buf, sizeof buf, 0);
        if (got < 0) {
            messages_.push_back("gamepad: disconnected " + status_);
            status_ = "no gamepad";
            close();
            return std::nullopt;
        }
        if (got == 0) break;
        auto s = pad::decodeReport(impl_->kind, impl_->descriptor,
                                   std::span<const uint8_t>(buf, size_t(got)));
        if (s) impl_->state = s;
    }
    return impl_->state;
}

std::vector<std::string> GamepadManager::takeMessages() { return std::exchange(messages_, {}); }

}  // namespace rg::viewer
