#!/usr/bin/env bash
# Installs what the system must supply for pointray's Vulkan path on Debian 12:
# the Vulkan loader, Mesa's lavapipe (>= 24.1, only in bookworm-backports) and the
# Khronos validation layer. The CPU backend needs none of this.
set -euo pipefail

if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; else SUDO=; fi
backports_list=/etc/apt/sources.list.d/pointray-backports.sources

add_backports_suite() {
    [ -f "$backports_list" ] && return 0
    local src=/etc/apt/sources.list.d/debian.sources
    if [ -f "$src" ]; then
        # Reuse the main archive's stanza (the one that is not the security archive),
        # with its Suites line rewritten.
        awk 'BEGIN{RS=""; ORS="\n\n"} !/security/ {sub(/Suites:[^\n]*/, "Suites: bookworm-backports"); print; exit}' "$src" \
            | $SUDO tee "$backports_list" >/dev/null
    elif [ -f /etc/apt/sources.list ]; then
        grep -E '^deb .* bookworm main' /etc/apt/sources.list | grep -v security | head -n1 \
            | sed 's/ bookworm main/ bookworm-backports main/' \
            | $SUDO tee /etc/apt/sources.list.d/pointray-backports.list >/dev/null
    else
        echo "install-system-deps: found no Debian apt source to derive bookworm-backports from" >&2
        exit 1
    fi
}

lavapipe_is_recent() {
    local v
    v=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)
    [ -n "$v" ] && dpkg --compare-versions "$v" ge 24.1
}

if lavapipe_is_recent && dpkg -s libvulkan1 vulkan-validationlayers xvfb >/dev/null 2>&1; then
    exit 0
fi

add_backports_suite
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq -t bookworm-backports mesa-vulkan-drivers >/dev/null
$SUDO apt-get install -y -qq libvulkan1 vulkan-validationlayers xvfb >/dev/null
lavapipe_is_recent || { echo "install-system-deps: lavapipe is older than 24.1" >&2; exit 1; }
