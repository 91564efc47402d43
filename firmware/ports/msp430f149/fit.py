#!/usr/bin/env python3
"""Does the MSP430F149 image fit? Prints flash and RAM use against the F149's 60 KB flash and
2 KB RAM (SLAS272H; msp430mcu memory.x: rom 0x1100-0xFFDF = 61 152 B, ram 0x0200-0x09FF =
2 048 B) and the worst-case stack depth, and exits 1 when it does not fit.

Stack depth: each function's frame from clang's -fstack-usage (.su files; a frame that is not
"static", a variable-length one, fails: it has no bound), plus 2 bytes of
return address per call, along the deepest path of the call graph read from the disassembly
(`call #addr`, and `br #addr` tail calls). An indirect call (the HAL's operations, the static
constructors) is taken to reach the deepest of the functions whose address the image stores
(the HAL table's and the constructors'). An interrupt adds 4 bytes (PC, SR) and its own
deepest path on top of the main loop's; the ISRs do not nest (GIE is cleared on entry), except
in the conversion's handlers (they switch interrupts on again) and the NMI (not maskable: it can
come on top of any of them).

Margin: the build fails unless RAM - (static + worst-case stack) >= MIN_MARGIN. The figure is a
ratchet, not a goal (docs/PERFORMANCE.md, "RAM"): what issue 32's third pass reached (22 B with
the NMI counted) less 6 B of slack (a frame's alignment, a flag); 24 B since the seventh pass
(the receive loop no longer under the commands' frames), so 18 now; so that real growth of RAM or
of the deepest path fails CI and has to be paid for. The goal is 10 % (205 B), which the F149 reaches only
by a protocol decision (the retransmit history) or the transmit ring and the history sharing
one buffer; raise the figure as RAM is recovered, never lower it.
  usage: fit.py ELF SU_DIR [LLVM_BIN_PREFIX]
"""
import pathlib
import re
import subprocess
import sys

FLASH = 61152
RAM = 2048
MIN_MARGIN = 18  # bytes (see above)
ISRS = ("isr_timer_a0", "isr_timer_a1", "isr_timer_b0", "isr_timer_b1", "isr_port2", "isr_usart0_rx",
        "isr_usart0_tx", "isr_nmi", "isr_unused")
NESTING = ("isr_port2", "isr_timer_a0")
# Assembly entries (runtime.cpp) have no .su file: the bytes each pushes before its call.
ASM_FRAMES = {f"__mspabi_{n}": 8 for n in ("mpyll", "divlli", "remlli")}
ASM_FRAMES.update({"__mspabi_divull": 16, "__mspabi_remull": 16})
ASM_FRAMES.update({"gyroflip_rt_udivmod32": 4, "gyroflip_rt_udivmod16": 0})
# What the interrupt handlers reach through the HAL table: the conversion's SPI, the stepper
# port, the tick counter, the step timer (main.cpp's handlers call nothing else through it).
ISR_HAL_OPS = re.compile(r"^_ZN12_GLOBAL__N_1\d+(spi_transfer|spi_select|stepper_port|ticks|"
                         r"step_timer)E")
HAL_OPS = re.compile(r"^_ZN12_GLOBAL__N_1\d+(spi_transfer|spi_select|rdy_low|stepper_port|"
                     r"home_switch|pwm_capture|uart_read|uart_write|ticks|watchdog_kick|busy_wait|"
                     r"stack_free|clock_faults|step_timer|critical|nv_read|nv_write)E")


def run(*args):
    return subprocess.run(args, check=True, capture_output=True, text=True).stdout


def sections(elf):
    out = {}
    for line in run("llvm-size", "-A", elf).splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[0].startswith("."):
            out[parts[0]] = int(parts[1])
    return out


def frames(su_dir):
    sizes = {}
    for su in pathlib.Path(su_dir).rglob("*.su"):
        for line in su.read_text().splitlines():
            loc, size, kind = line.rsplit("\t", 2)
            if kind != "static":
                sys.exit(f"fit: {loc} has a {kind} frame: no static stack bound")
            sizes[loc.rsplit(":", 1)[-1]] = int(size)
    sizes.update(ASM_FRAMES)
    return sizes


def call_graph(elf):
    graph, starts, current = {}, {}, None
    for line in run("llvm-objdump", "-d", "--no-show-raw-insn", elf).splitlines():
        m = re.match(r"^([0-9a-f]+) <(.+)>:$", line)
        if m:
            current = m.group(2)
            starts[int(m.group(1), 16)] = current
            graph[current] = set()
            continue
        if current is None:
            continue
        m = re.search(r"\b(call|br)\s+#(\d+)\b", line)
        if m:
            graph[current].add(int(m.group(2)))
        elif re.search(r"\bcall\s+r\d+", line):
            graph[current].add("indirect")
    for f, callees in graph.items():
        graph[f] = {starts.get(c, c) if c != "indirect" else c for c in callees}
    return graph


def depth(fn, graph, sizes, indirect, memo, path=()):
    if fn in path:
        sys.exit(f"fit: recursion through {fn}: no static stack bound")
    if fn in memo:
        return memo[fn]
    deepest = 0
    for c in graph.get(fn, ()):
        targets = indirect if c == "indirect" else [c]
        for t in targets:
            if isinstance(t, str) and t in graph:
                deepest = max(deepest, 2 + depth(t, graph, sizes, indirect, memo, path + (fn,)))
    memo[fn] = sizes.get(fn, 0) + deepest
    return memo[fn]


def main():
    elf, su_dir = sys.argv[1], sys.argv[2]
    sec = sections(elf)
    graph, sizes = call_graph(elf), frames(su_dir)
    indirect = [f for f in graph if HAL_OPS.match(f) or f.startswith("_GLOBAL__sub_I_")]
    memo = {}
    main_depth = 2 + depth("continue_reset", graph, sizes, indirect, memo)
    isr_indirect = [f for f in graph if ISR_HAL_OPS.match(f)]
    isr_memo = {}
    isr = {i: 4 + depth(i, graph, sizes, isr_indirect, isr_memo) for i in ISRS if i in graph}
    # The conversion's handlers switch interrupts on again (main.cpp): any other handler may
    # nest in them once.
    plain = max(d for i, d in isr.items() if i not in NESTING)
    isr_depth = max([plain] + [isr[i] + plain for i in NESTING if i in isr])
    isr_depth += isr.get("isr_nmi", 0)
    stack = main_depth + isr_depth
    flash = sum(sec.get(s, 0) for s in (".text", ".rodata", ".init_array", ".data"))
    ram = sec.get(".data", 0) + sec.get(".bss", 0) + sec.get(".noinit", 0)
    print(f"msp430f149: .text {sec.get('.text', 0)} B, .rodata {sec.get('.rodata', 0)} B, "
          f".data {sec.get('.data', 0)} B, .bss {sec.get('.bss', 0)} B")
    print(f"msp430f149: flash {flash} / {FLASH} B ({100 * flash / FLASH:.1f} %), "
          f"RAM {ram} + stack {stack} (main {main_depth} + interrupt {isr_depth}) = "
          f"{ram + stack} / {RAM} B ({100 * (ram + stack) / RAM:.1f} %), margin {RAM - ram - stack} B "
          f"(at least {MIN_MARGIN})")
    floats = sorted(f for f in graph if re.match(
        r"__mspabi_((add|sub|mpy|div|cmp|neg)(f|d)|fix|flt|cvt)|__(add|sub|mul|div)(s|d)f3", f))
    if floats:
        sys.exit(f"msp430f149: floating point at run time: {', '.join(floats)}")
    if flash > FLASH or ram + stack > RAM:
        sys.exit("msp430f149: the image does not fit the MSP430F149")
    if RAM - ram - stack < MIN_MARGIN:
        sys.exit(f"msp430f149: RAM margin {RAM - ram - stack} B is below the {MIN_MARGIN} B floor "
                 "(fit.py: recover RAM before adding any)")


if __name__ == "__main__":
    main()
