#!/usr/bin/env python3
"""gtkw_dump_args.py — prints the rtsim arguments, one a line, of the dump
command written in a GTKWave view's header comment (waveforms/*.gtkw):

    [*]   build/bin/rtsim interior --res 64x36 --vcd waveforms/rtsim.vcd \\
    [*]       --vcd-window 0:5000 --vcd-filter 'trv0.*,ist.*,sched.*'
    [*] then: gtkwave waveforms/rtsim.vcd waveforms/trv_pipeline.gtkw

so that the view's test (testbench/scripts/tb_waveform_views.sh) and its screenshot
(scripts/render-waveform-views.sh) make the very dump the view documents.
Usage: gtkw_dump_args.py VIEW.gtkw
Arguments:
    VIEW.gtkw    the GTKWave view whose header comment holds the command
    -h, --help   this text
Exit 2 when the header holds no "build/bin/rtsim ..." command."""
import shlex
import signal
import sys

# a reader that stops early (`| head`) ends this quietly, as it does a C tool
signal.signal(signal.SIGPIPE, signal.SIG_DFL)

if sys.argv[1:2] in (["-h"], ["--help"]):
    print(__doc__)
    sys.exit(0)
if len(sys.argv) != 2:
    sys.exit("usage: gtkw_dump_args.py VIEW.gtkw")
with open(sys.argv[1]) as f:
    text = " ".join(l[3:].strip() for l in f if l.startswith("[*]"))
text = text.replace("\\ ", " ")  # "\" line continuations
if "build/bin/rtsim " not in text:
    print("%s: no 'build/bin/rtsim ...' dump command in the header comment" % sys.argv[1],
          file=sys.stderr)
    sys.exit(2)
# the command ends where the header's next sentence ("then: gtkwave ...") starts
command = text.split("build/bin/rtsim ", 1)[1].split(" then: ", 1)[0]
print("\n".join(shlex.split(command)))
