#!/usr/bin/env python3
"""The rig's controller board as a KiCad 6 schematic, written from the design table below
(docs/HARDWARE.md, "Schematic, BOM and bring-up"). KiCad is not installed here (Debian's 6.0
package has no command-line ERC or netlist export and brings ~1 GB of libraries), so the file is
generated: every part a box symbol with its pins, every pin joined to its net by a label at its
end (KiCad joins same-named labels on a sheet), which ERC and netlisting in KiCad 6 or later read.

  schematic.py            writes gyroflip_rig.kicad_sch and bom.csv next to this script
  schematic.py --check    fails (exit 1) unless both files are what this table writes, every
                          connection the firmware relies on (PIN_MAP, docs/HARDWARE.md) is in the
                          netlist, every power pin has a net, and no net has a single pin

Pin numbers marked [U] in the notes are read from the parts' data sheets as recalled here: check
them against your parts' data sheets before you etch a board (the firmware needs the nets, not the
numbers).
"""
import csv
import io
import pathlib
import sys
import uuid

HERE = pathlib.Path(__file__).resolve().parent
SCH = HERE / "gyroflip_rig.kicad_sch"
BOM = HERE / "bom.csv"

# Parts: reference, value, footprint, the note for the BOM, and pins (number, name, net). A net
# of None leaves the pin unconnected (marked no-connect).
PARTS = []


def part(ref, value, footprint, note, pins, bom=True):
    PARTS.append({"ref": ref, "value": value, "footprint": footprint, "note": note,
                  "pins": pins, "bom": bom})


# MSP430F149IPM, LQFP-64 (SLAS272H, pin-out of the PM package). Unused port pins are outputs
# driven low by the firmware (main.cpp init_pins): left unconnected.
F149 = [
    ("1", "DVCC", "+3V3"), ("2", "P6.3", "M0_B'"), ("3", "P6.4", "M1_A"), ("4", "P6.5", "M1_B"),
    ("5", "P6.6", "M1_A'"), ("6", "P6.7", "M1_B'"), ("7", "VREF+", None), ("8", "XIN", "LFXT_IN"),
    ("9", "XOUT", "LFXT_OUT"), ("10", "VeREF+", None), ("11", "VREF-", "GND"),
    ("12", "P1.0", None), ("13", "P1.1/BSL_TX", "BSL_TX"), ("14", "P1.2", None),
    ("15", "P1.3", None), ("16", "P1.4", None), ("17", "P1.5", None), ("18", "P1.6", None),
    ("19", "P1.7", None), ("20", "P2.0", "ADC_RDY"), ("21", "P2.1", "HOME"),
    ("22", "P2.2/BSL_RX", "BSL_RX"), ("23", "P2.3", None), ("24", "P2.4", None),
    ("25", "P2.5", None), ("26", "P2.6", None), ("27", "P2.7", None), ("28", "P3.0", None),
    ("29", "P3.1", None), ("30", "P3.2", None), ("31", "P3.3", None), ("32", "P3.4/UTXD0", "MCU_TX"),
    ("33", "P3.5/URXD0", "MCU_RX"), ("34", "P3.6", None), ("35", "P3.7", None),
    ("36", "P4.0", None), ("37", "P4.1/TB1", "ACC_X"), ("38", "P4.2/TB2", "ACC_Y"),
    ("39", "P4.3", None), ("40", "P4.4", None), ("41", "P4.5", None), ("42", "P4.6", None),
    ("43", "P4.7", None), ("44", "P5.0", "ADC_CS"), ("45", "P5.1/SIMO1", "ADC_DIN"),
    ("46", "P5.2/SOMI1", "ADC_DOUT"), ("47", "P5.3/UCLK1", "ADC_SCLK"), ("48", "P5.4", "ADC_RESET"),
    ("49", "P5.5", None), ("50", "P5.6", None), ("51", "P5.7", None), ("52", "XT2OUT", "XT2_OUT"),
    ("53", "XT2IN", "XT2_IN"), ("54", "TDO/TDI", "JTAG_TDO"), ("55", "TDI/TCLK", "JTAG_TDI"),
    ("56", "TMS", "JTAG_TMS"), ("57", "TCK", "JTAG_TCK"), ("58", "RST/NMI", "RST"),
    ("59", "P6.0", "M0_A"), ("60", "P6.1", "M0_B"), ("61", "P6.2", "M0_A'"), ("62", "AVSS", "GND"),
    ("63", "DVSS", "GND"), ("64", "AVCC", "+3V3A"),
]
part("U1", "MSP430F149IPM", "Package_QFP:LQFP-64_10x10mm_P0.5mm",
     "MCU, 60 KB flash, 2 KB RAM; no brown-out reset (U3 supervises)", F149)

# AD7739BRU, TSSOP-28 [U: pin numbers]. DVDD at 3.3 V (SPI levels of the MCU), AVDD at 5 V.
part("U2", "AD7739BRU", "Package_SO:TSSOP-28_4.4x9.7mm_P0.65mm",
     "24-bit ADC, 8 channels; [U] pin numbers", [
         ("1", "SCLK", "ADC_SCLK"), ("2", "MCLKIN", "ADC_XIN"), ("3", "MCLKOUT", "ADC_XOUT"),
         ("4", "/CS", "ADC_CS"), ("5", "/RESET", "ADC_RESET"), ("6", "AVDD", "+5VA"),
         ("7", "AGND", "GND"), ("8", "AIN0", "GYRO_RATE"), ("9", "AIN1", "REF_BUF"),
         ("10", "AIN2", "GYRO_TEMP"), ("11", "AIN3", "REF_2V5"), ("12", "AIN4", "GND"),
         ("13", "AIN5", "GND"), ("14", "AIN6", "GND"), ("15", "AIN7", "GND"),
         ("16", "AINCOM", "GND"), ("17", "REFIN(-)", "GND"), ("18", "REFIN(+)", "REF_2V5"),
         ("19", "P0", None), ("20", "P1", None), ("21", "BIASOUT", None), ("22", "AGND", "GND"),
         ("23", "DGND", "GND"), ("24", "DVDD", "+3V3"), ("25", "/RDY", "ADC_RDY"),
         ("26", "DOUT", "ADC_DOUT"), ("27", "DIN", "ADC_DIN"), ("28", "DGND", "GND"),
     ])

# The supervisor the F149 needs: it has a power-on reset but no brown-out reset, and below
# ~2.45 V it cannot run 5.53 MHz (SLAS272: 4.15 MHz at 1.8 V to 8 MHz at 3.6 V). TPS3808G30:
# 2.79 V threshold, open-drain /RESET (the JTAG tool drives RST/NMI too), delay set by C_T.
part("U3", "TPS3808G30DBV", "Package_TO_SOT_SMD:SOT-23-6",
     "supply supervisor, 2.79 V, open drain [U] pin numbers", [
         ("1", "/RESET", "RST"), ("2", "GND", "GND"), ("3", "/MR", "+3V3"), ("4", "CT", "SUP_CT"),
         ("5", "SENSE", "+3V3"), ("6", "VDD", "+3V3"),
     ])
part("U4", "MAX3232ECD", "Package_SO:SOIC-16_3.9x9.9mm_P1.27mm", "RS-232 transceiver, 3.3 V", [
    ("1", "C1+", "RS_C1P"), ("2", "V+", "RS_VP"), ("3", "C1-", "RS_C1N"), ("4", "C2+", "RS_C2P"),
    ("5", "C2-", "RS_C2N"), ("6", "V-", "RS_VN"), ("7", "T2OUT", None), ("8", "R2IN", None),
    ("9", "R2OUT", None), ("10", "T2IN", "GND"), ("11", "T1IN", "MCU_TX"), ("12", "R1OUT", "MCU_RX"),
    ("13", "R1IN", "RS232_RX"), ("14", "T1OUT", "RS232_TX"), ("15", "GND", "GND"),
    ("16", "VCC", "+3V3"),
])
for ref, motor in (("U5", "M0"), ("U6", "M1")):
    part(ref, "ULN2003A", "Package_SO:SOIC-16_3.9x9.9mm_P1.27mm",
         f"Darlington driver, motor {motor[1]} (flyback diodes to COM)", [
             ("1", "IN1", f"{motor}_A"), ("2", "IN2", f"{motor}_B"), ("3", "IN3", f"{motor}_A'"),
             ("4", "IN4", f"{motor}_B'"), ("5", "IN5", "GND"), ("6", "IN6", "GND"),
             ("7", "IN7", "GND"), ("8", "GND", "GND"), ("9", "COM", "+12V"),
             ("10", "OUT7", None), ("11", "OUT6", None), ("12", "OUT5", None),
             ("13", "OUT4", f"{motor}_COIL_B'"), ("14", "OUT3", f"{motor}_COIL_A'"),
             ("15", "OUT2", f"{motor}_COIL_B"), ("16", "OUT1", f"{motor}_COIL_A"),
         ])
part("U7", "ADR421BRZ", "Package_SO:SOIC-8_3.9x4.9mm_P1.27mm", "2.5 V reference, 0.04 % [U] pins", [
    ("2", "VIN", "+5VA"), ("4", "GND", "GND"), ("6", "VOUT", "REF_2V5"), ("1", "NC", None),
    ("3", "NC", None), ("5", "TRIM", None), ("7", "NC", None), ("8", "NC", None),
])
# The reference buffer: AIN1's input (the HZ1-90-100A's null) must not load the reference.
part("U8", "AD8605ARTZ", "Package_TO_SOT_SMD:SOT-23-5", "op-amp follower, rail to rail [U] pins", [
    ("1", "OUT", "REF_BUF"), ("2", "V-", "GND"), ("3", "+IN", "REF_2V5"), ("4", "-IN", "REF_BUF"),
    ("5", "V+", "+5VA"),
])
part("U9", "TLV1117LV33DCY", "Package_TO_SOT_SMD:SOT-223-3_TabPin2", "3.3 V LDO, 1 A", [
    ("1", "GND", "GND"), ("2", "OUT", "+3V3"), ("3", "IN", "+5V"),
])
part("U10", "LM7805", "Package_TO_SOT_THT:TO-220-3_Vertical", "5 V regulator from 12 V", [
    ("1", "IN", "+12V"), ("2", "GND", "GND"), ("3", "OUT", "+5V"),
])
part("FB1", "BLM18PG221", "Inductor_SMD:L_0603_1608Metric", "ferrite: analog 5 V", [
    ("1", "1", "+5V"), ("2", "2", "+5VA")])
part("FB2", "BLM18PG221", "Inductor_SMD:L_0603_1608Metric", "ferrite: MCU AVCC", [
    ("1", "1", "+3V3"), ("2", "2", "+3V3A")])

# Crystals and their load capacitors. LFXT1 in LF mode has its load capacitance on chip
# (SLAU049 §4: a watch crystal connects to XIN and XOUT without other parts); XT2 and the
# AD7739's crystal need C = 2 (C_L - C_stray): 22 pF for a 14-pF crystal with ~3 pF of board.
part("Y1", "32.768 kHz", "Crystal:Crystal_C26-LF_D2.1mm_L6.5mm_Horizontal", "watch crystal, 6 pF CL", [
    ("1", "1", "LFXT_IN"), ("2", "2", "LFXT_OUT")])
part("Y2", "5.5296 MHz", "Crystal:Crystal_HC49-U_Vertical", "XT2: 115200 x 48, CL 14 pF", [
    ("1", "1", "XT2_IN"), ("2", "2", "XT2_OUT")])
part("Y3", "6.144 MHz", "Crystal:Crystal_HC49-U_Vertical", "AD7739 MCLK, CL 14 pF", [
    ("1", "1", "ADC_XIN"), ("2", "2", "ADC_XOUT")])


def cap(ref, value, a, b, note, fp="Capacitor_SMD:C_0603_1608Metric"):
    part(ref, value, fp, note, [("1", "1", a), ("2", "2", b)])


def res(ref, value, a, b, note):
    part(ref, value, "Resistor_SMD:R_0603_1608Metric", note, [("1", "1", a), ("2", "2", b)])


cap("C1", "22p", "XT2_IN", "GND", "XT2 load, C0G")
cap("C2", "22p", "XT2_OUT", "GND", "XT2 load, C0G")
cap("C3", "22p", "ADC_XIN", "GND", "AD7739 crystal load, C0G")
cap("C4", "22p", "ADC_XOUT", "GND", "AD7739 crystal load, C0G")
cap("C5", "100n", "+3V3", "GND", "U1 DVCC decoupling, at pin 1")
cap("C6", "10u", "+3V3", "GND", "U1 bulk", "Capacitor_SMD:C_0805_2012Metric")
cap("C7", "100n", "+3V3A", "GND", "U1 AVCC decoupling, at pin 64")
cap("C8", "100n", "+5VA", "GND", "U2 AVDD decoupling")
cap("C9", "10u", "+5VA", "GND", "U2 AVDD bulk", "Capacitor_SMD:C_0805_2012Metric")
cap("C10", "100n", "+3V3", "GND", "U2 DVDD decoupling")
cap("C11", "100n", "REF_2V5", "GND", "reference output")
cap("C12", "1u", "REF_2V5", "GND", "reference output bulk [U: the ADR421's stable range]")
cap("C13", "100n", "+5VA", "GND", "U7, U8 supply")
cap("C14", "100n", "RS_C1P", "RS_C1N", "MAX3232 charge pump")
cap("C15", "100n", "RS_C2P", "RS_C2N", "MAX3232 charge pump")
cap("C16", "100n", "RS_VP", "+3V3", "MAX3232 V+ reservoir")
cap("C17", "100n", "RS_VN", "GND", "MAX3232 V- reservoir")
cap("C18", "100n", "+3V3", "GND", "U4 decoupling")
cap("C19", "10n", "SUP_CT", "GND", "supervisor delay: ~40 ms [U: t = C_T x 4 ms/nF + 0.5 ms]")
cap("C20", "10u", "+3V3", "GND", "LDO output", "Capacitor_SMD:C_0805_2012Metric")
cap("C21", "10u", "+5V", "GND", "LDO input, 7805 output", "Capacitor_SMD:C_0805_2012Metric")
cap("C22", "100u", "+12V", "GND", "motor supply bulk", "Capacitor_THT:CP_Radial_D8.0mm_P3.50mm")
cap("C23", "330n", "+12V", "GND", "7805 input")
cap("C24", "100n", "HOME", "GND", "home switch RC filter (1 ms with R2)")
cap("C25", "100n", "+5V", "GND", "gyro and accelerometer supply at J6, J7")
res("R1", "47k", "RST", "+3V3", "RST/NMI pull-up (the supervisor is open drain)")
res("R2", "10k", "HOME", "+3V3", "home switch pull-up (closed = low)")
res("R3", "100k", "BSL_RX", "+3V3", "P2.2 (BSL receive) defined without an adapter")
res("R4", "125k", "ACC_RSET", "GND", "ADXL202 RSET: T2 = 1 ms")

# Connectors.
part("J1", "DB9 female", "Connector_Dsub:DSUB-9_Female_Horizontal_P2.77x2.84mm_EdgePinOffset7.70mm",
     "RS-232 to the PC (DCE)", [
         ("2", "RXD", "RS232_TX"), ("3", "TXD", "RS232_RX"), ("5", "GND", "GND"),
         ("1", "DCD", None), ("4", "DTR", None), ("6", "DSR", None), ("7", "RTS", None),
         ("8", "CTS", None), ("9", "RI", None)])
part("J2", "TI JTAG 14", "Connector_IDC:IDC-Header_2x07_P2.54mm_Vertical",
     "MSP-FET430UIF 14-pin JTAG (SLAU138)", [
         ("1", "TDO/TDI", "JTAG_TDO"), ("2", "VCC_TOOL", None), ("3", "TDI/VPP", "JTAG_TDI"),
         ("4", "VCC_TARGET", "+3V3"), ("5", "TMS", "JTAG_TMS"), ("6", "NC", None),
         ("7", "TCK", "JTAG_TCK"), ("8", "TEST", None), ("9", "GND", "GND"), ("10", "NC", None),
         ("11", "RST/NMI", "RST"), ("12", "NC", None), ("13", "NC", None), ("14", "NC", None)])
part("J3", "BSL 6", "Connector_PinHeader_2.54mm:PinHeader_1x06_P2.54mm_Vertical",
     "bootstrap loader (SLAU319: P1.1 transmit, P2.2 receive, RST and TCK sequence)", [
         ("1", "+3V3", "+3V3"), ("2", "TX", "BSL_TX"), ("3", "RX", "BSL_RX"),
         ("4", "RST", "RST"), ("5", "TCK", "JTAG_TCK"), ("6", "GND", "GND")])
for ref, motor in (("J4", "M0"), ("J5", "M1")):
    part(ref, f"motor {motor[1]}", "Connector_PinHeader_2.54mm:PinHeader_1x06_P2.54mm_Vertical",
         "unipolar stepper, centre taps to +12 V", [
             ("1", "A", f"{motor}_COIL_A"), ("2", "B", f"{motor}_COIL_B"),
             ("3", "A'", f"{motor}_COIL_A'"), ("4", "B'", f"{motor}_COIL_B'"),
             ("5", "COM", "+12V"), ("6", "COM", "+12V")])
part("J6", "gyro", "Connector_PinHeader_2.54mm:PinHeader_1x05_P2.54mm_Vertical",
     "ADXRS150 or HZ1-90-100A: rate, temperature", [
         ("1", "+5V", "+5V"), ("2", "GND", "GND"), ("3", "RATE", "GYRO_RATE"),
         ("4", "TEMP", "GYRO_TEMP"), ("5", "REF", None)])
part("J7", "accelerometer", "Connector_PinHeader_2.54mm:PinHeader_1x05_P2.54mm_Vertical",
     "ADXL202 duty-cycle outputs", [
         ("1", "VDD", "+3V3"), ("2", "GND", "GND"), ("3", "XOUT", "ACC_X"),
         ("4", "YOUT", "ACC_Y"), ("5", "RSET", "ACC_RSET")])
part("J8", "home switch", "Connector_PinHeader_2.54mm:PinHeader_1x02_P2.54mm_Vertical",
     "closes to GND at home", [("1", "SW", "HOME"), ("2", "GND", "GND")])
part("J9", "12 V in", "Connector_BarrelJack:BarrelJack_Horizontal", "motor and board supply", [
    ("1", "+", "+12V"), ("2", "-", "GND")])

# What the firmware relies on (docs/HARDWARE.md, pin map): (net, [(ref, pin name)]).
PIN_MAP = [
    ("ADC_RDY", [("U1", "P2.0"), ("U2", "/RDY")]),
    ("ADC_CS", [("U1", "P5.0"), ("U2", "/CS")]),
    ("ADC_DIN", [("U1", "P5.1/SIMO1"), ("U2", "DIN")]),
    ("ADC_DOUT", [("U1", "P5.2/SOMI1"), ("U2", "DOUT")]),
    ("ADC_SCLK", [("U1", "P5.3/UCLK1"), ("U2", "SCLK")]),
    ("ADC_RESET", [("U1", "P5.4"), ("U2", "/RESET")]),
    ("HOME", [("U1", "P2.1"), ("J8", "SW"), ("R2", "1")]),
    ("MCU_TX", [("U1", "P3.4/UTXD0"), ("U4", "T1IN")]),
    ("MCU_RX", [("U1", "P3.5/URXD0"), ("U4", "R1OUT")]),
    ("ACC_X", [("U1", "P4.1/TB1"), ("J7", "XOUT")]),
    ("ACC_Y", [("U1", "P4.2/TB2"), ("J7", "YOUT")]),
    ("M0_A", [("U1", "P6.0"), ("U5", "IN1")]), ("M0_B", [("U1", "P6.1"), ("U5", "IN2")]),
    ("M0_A'", [("U1", "P6.2"), ("U5", "IN3")]), ("M0_B'", [("U1", "P6.3"), ("U5", "IN4")]),
    ("M1_A", [("U1", "P6.4"), ("U6", "IN1")]), ("M1_B", [("U1", "P6.5"), ("U6", "IN2")]),
    ("M1_A'", [("U1", "P6.6"), ("U6", "IN3")]), ("M1_B'", [("U1", "P6.7"), ("U6", "IN4")]),
    ("XT2_IN", [("U1", "XT2IN"), ("Y2", "1"), ("C1", "1")]),
    ("XT2_OUT", [("U1", "XT2OUT"), ("Y2", "2"), ("C2", "1")]),
    ("LFXT_IN", [("U1", "XIN"), ("Y1", "1")]), ("LFXT_OUT", [("U1", "XOUT"), ("Y1", "2")]),
    ("RST", [("U1", "RST/NMI"), ("U3", "/RESET"), ("R1", "1"), ("J2", "RST/NMI"), ("J3", "RST")]),
    ("BSL_TX", [("U1", "P1.1/BSL_TX"), ("J3", "TX")]),
    ("BSL_RX", [("U1", "P2.2/BSL_RX"), ("J3", "RX"), ("R3", "1")]),
    ("REF_BUF", [("U8", "OUT"), ("U2", "AIN1")]),
    ("REF_2V5", [("U7", "VOUT"), ("U2", "REFIN(+)"), ("U2", "AIN3"), ("U8", "+IN")]),
    ("GYRO_RATE", [("U2", "AIN0"), ("J6", "RATE")]),
    ("GYRO_TEMP", [("U2", "AIN2"), ("J6", "TEMP")]),
]
# Power-named pins left open on purpose: the board powers itself, so the FET's supply
# output (JTAG pin 2) stays unconnected and the tool senses the board on pin 4 (SLAU138).
LEFT_OPEN = {("J2", "VCC_TOOL")}
POWER_NAMES = ("VCC", "VDD", "AVDD", "DVDD", "AVCC", "DVCC", "V+", "GND", "AVSS", "DVSS", "AGND",
               "DGND", "COM", "VIN", "IN", "OUT")


def uid(*key):
    return str(uuid.uuid5(uuid.NAMESPACE_URL, "gyroflip-rig/" + "/".join(key)))


def font():
    return "(effects (font (size 1.27 1.27)))"


def write_schematic():
    out = io.StringIO()
    w = out.write
    w("(kicad_sch (version 20211123) (generator gyroflip_schematic_py)\n")
    w(f"  (uuid {uid('sheet')})\n  (paper \"A1\")\n")
    w('  (title_block (title "gyroflip rig controller (MSP430F149, AD7739, two unipolar '
      'steppers)") (comment 1 "generated by firmware/ports/msp430f149/board/schematic.py") '
      '(comment 2 "docs/HARDWARE.md: pin map, BOM, bring-up"))\n')
    w("  (lib_symbols\n")
    for p in PARTS:
        n = len(p["pins"])
        half = (n + 1) // 2
        height = 2.54 * (half + 1)
        name = f"gyroflip:{p['ref']}"
        w(f'    (symbol "{name}" (in_bom yes) (on_board yes)\n')
        w(f'      (property "Reference" "{p["ref"][0]}" (id 0) (at 0 {height / 2 + 2.54:.2f} 0) {font()})\n')
        w(f'      (property "Value" "{p["value"]}" (id 1) (at 0 {-height / 2 - 2.54:.2f} 0) {font()})\n')
        w(f'      (symbol "{p["ref"]}_0_1" (rectangle (start -10.16 {height / 2:.2f}) '
          f'(end 10.16 {-height / 2:.2f}) (stroke (width 0.254) (type default) (color 0 0 0 0)) '
          '(fill (type background))))\n')
        w(f'      (symbol "{p["ref"]}_1_1"\n')
        for i, (num, pname, _net) in enumerate(p["pins"]):
            x, y, ang = pin_at(i, half, height)
            w(f'        (pin passive line (at {x:.2f} {y:.2f} {ang}) (length 2.54) '
              f'(name "{esc(pname)}" {font()}) (number "{num}" {font()}))\n')
        w("      )\n    )\n")
    w("  )\n")
    col = 0
    for k, p in enumerate(PARTS):
        n = len(p["pins"])
        half = (n + 1) // 2
        height = 2.54 * (half + 1)
        sx, sy = origin(k)
        w(f'  (symbol (lib_id "gyroflip:{p["ref"]}") (at {sx:.2f} {sy:.2f} 0) (unit 1) '
          f'(in_bom {"yes" if p["bom"] else "no"}) (on_board yes) (uuid {uid(p["ref"])})\n')
        w(f'    (property "Reference" "{p["ref"]}" (id 0) (at {sx:.2f} {sy - height / 2 - 2.54:.2f} 0) {font()})\n')
        w(f'    (property "Value" "{esc(p["value"])}" (id 1) (at {sx:.2f} {sy + height / 2 + 2.54:.2f} 0) {font()})\n')
        w(f'    (property "Footprint" "{p["footprint"]}" (id 2) (at {sx:.2f} {sy:.2f} 0) '
          '(effects (font (size 1.27 1.27)) hide))\n')
        for num, _n, _net in p["pins"]:
            w(f'    (pin "{num}" (uuid {uid(p["ref"], "pin", num)}))\n')
        w("  )\n")
        for i, (num, _pname, net) in enumerate(p["pins"]):
            x, y, ang = pin_at(i, half, height)
            # The pin's end in sheet coordinates (the library's y axis points up).
            ex, ey = sx + x, sy - y
            if net is None:
                w(f"  (no_connect (at {ex:.2f} {ey:.2f}) (uuid {uid(p['ref'], 'nc', num)}))\n")
            else:
                rot = 180 if ang == 0 else 0
                w(f'  (label "{esc(net)}" (at {ex:.2f} {ey:.2f} {rot}) '
                  f'(effects (font (size 1.27 1.27)) (justify {"right" if rot == 180 else "left"})) '
                  f'(uuid {uid(p["ref"], "label", num)}))\n')
        col += 1
    w("  (sheet_instances (path \"/\" (page \"1\")))\n)\n")
    return out.getvalue()


def esc(s):
    return s.replace("\\", "\\\\").replace('"', '\\"')


def pin_at(i, half, height):
    # Left column pins point right (angle 0) from x = -12.70; right column point left (180).
    row = i if i < half else i - half
    y = height / 2 - 2.54 * (row + 1)
    return (-12.70, y, 0) if i < half else (12.70, y, 180)


def origin(k):
    # A grid of boxes, 8 across, on 2.54 mm.
    return 40.64 + (k % 8) * 83.82, 50.80 + (k // 8) * 101.60


def write_bom():
    out = io.StringIO()
    c = csv.writer(out, lineterminator="\n")
    c.writerow(["reference", "value", "footprint", "note"])
    for p in PARTS:
        if p["bom"]:
            c.writerow([p["ref"], p["value"], p["footprint"], p["note"]])
    return out.getvalue()


def netlist():
    nets = {}
    for p in PARTS:
        for num, pname, net in p["pins"]:
            if net is not None:
                nets.setdefault(net, []).append((p["ref"], pname, num))
    return nets


def firmware_directions():
    """Port -> direction byte as main.cpp's init_pins sets it (PnDIR = ...)."""
    import re
    text = (HERE.parent / "main.cpp").read_text()
    body = text[text.index("void init_pins()"):]
    body = body[:body.index("\n}")]
    dirs = {}
    for port, expr in re.findall(r"P([1-6])DIR = ([^;]+);", body):
        expr = re.sub(r"static_cast<uint8_t>", "", expr)
        expr = re.sub(r"(0x[0-9A-Fa-f]+)u", r"\1", expr)
        dirs[int(port)] = eval(expr, {"__builtins__": {}}) & 0xFF  # noqa: S307 (hex, ~, |)
    return dirs


def check():
    problems = []
    # A port pin left unconnected must be one the firmware drives (an output), never a floating
    # input: the F149 has no internal pull resistors (SLAU049 §9).
    dirs = firmware_directions()
    for num, pname, net in next(p for p in PARTS if p["ref"] == "U1")["pins"]:
        if net is None and pname.startswith("P") and "." in pname:
            port, bit = int(pname[1]), int(pname[3])
            if port not in dirs or not dirs[port] >> bit & 1:
                problems.append(f"U1 {pname} is unconnected but not an output in init_pins")
    if not SCH.exists() or SCH.read_text() != write_schematic():
        problems.append(f"{SCH.name} is not what schematic.py writes (run it)")
    if not BOM.exists() or BOM.read_text() != write_bom():
        problems.append(f"{BOM.name} is not what schematic.py writes (run it)")
    nets = netlist()
    for net, pins in PIN_MAP:
        have = {(r, n) for r, n, _ in nets.get(net, [])}
        for ref, pname in pins:
            if (ref, pname) not in have:
                problems.append(f"net {net}: {ref} pin {pname} is not on it")
    for net, pins in nets.items():
        if len(pins) < 2:
            problems.append(f"net {net} has one pin only ({pins[0][0]} {pins[0][1]})")
    for p in PARTS:
        for num, pname, net in p["pins"]:
            if (p["ref"], pname) in LEFT_OPEN:
                continue
            if net is None and any(pname == s or pname.startswith(s) for s in POWER_NAMES[:6]):
                problems.append(f"{p['ref']} power pin {pname} ({num}) has no net")
        nums = [num for num, _n, _net in p["pins"]]
        if len(nums) != len(set(nums)):
            problems.append(f"{p['ref']}: a pin number twice")
    refs = [p["ref"] for p in PARTS]
    if len(refs) != len(set(refs)):
        problems.append("a reference twice")
    for problem in problems:
        sys.stderr.write(f"schematic: {problem}\n")
    if not problems:
        print(f"schematic: {len(PARTS)} parts, {len(nets)} nets, the firmware's {len(PIN_MAP)} "
              "connections present")
    return 1 if problems else 0


def main(argv):
    if argv[1:] == ["--check"]:
        return check()
    if argv[1:]:
        print(__doc__.strip())
        return 0 if argv[1:] in (["-h"], ["--help"]) else 2
    SCH.write_text(write_schematic())
    BOM.write_text(write_bom())
    return check()


if __name__ == "__main__":
    sys.exit(main(sys.argv))
