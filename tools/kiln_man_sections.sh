#!/bin/sh
# The man page's sections beyond 'kiln --help' (help2man --include): every command's options as
# its own --help prints them, the exit status, the environment and the files. Run at build time
# by CMake with the built binary: tools/kiln_man_sections.sh KILN kiln.h2m
set -eu
kiln=$1
exec >"$2"
# roff: a line starting with '.' or "'" would be a request; a backslash an escape.
verbatim() { sed -e 's/\\/\\e/g' -e "s/^\([.']\)/\\\\\&\1/"; }
echo "[COMMANDS AND THEIR OPTIONS]"
for command in render merge info crosscheck "bench accel" "bench plan" "bench accuracy" batch \
    "farm submit" "farm status" "farm merge" "farm resubmit" "tools subdivide" "report cs184"; do
    echo ".SS kiln $command"
    echo ".nf"
    # shellcheck disable=SC2086 # the subcommand is two words on purpose
    "$kiln" $command --help 2>&1 | verbatim
    echo ".fi"
done
cat <<'SECTIONS'
[EXIT STATUS]
.TP
.B 0
done
.TP
.B 1
a failure: an output could not be written, a check found a fault, a batch render or farm shard failed
.TP
.B 2
bad input or usage: a scene, job file, option or OCIO config refused before any work
.TP
.B 3
kiln render: \-\-time\-limit reached; OUT.ckpt and the image so far are written (\-\-resume goes on)
.TP
.B 130
interrupted (SIGINT, SIGTERM): the checkpoint (with checkpoints on) and the image so far are written
[ENVIRONMENT]
.TP
.B OCIO
the OpenColorIO config for the working space, the display and the view; unset: PREFIX/share/kiln/config.ocio beside the binary
.TP
.B KILN_TEXTURE_CACHE
where plain images are kept as tiled MIP files (default $XDG_CACHE_HOME/kiln/textures, else ~/.cache/kiln/textures)
.TP
.B KILN_MEMORY_LIMIT
the memory kiln may plan for, in bytes (default: what the machine or its cgroup has)
.TP
.B SLURM_CONF, PATH
kiln farm runs the Slurm client (sbatch, scontrol, scancel) found on PATH with its configuration
.TP
.B SLURM_ARRAY_TASK_ID, SLURM_JOB_ID, SLURM_RESTART_COUNT
read by kiln farm run\-shard inside a Slurm task: the shard, the job to requeue before its time limit, the run
.TP
.B COLUMNS
the width of the progress bar when the terminal does not say
[FILES]
.TP
.I PREFIX/share/kiln/config.ocio
the OCIO config used when $OCIO is unset
.TP
.I OUT.exr, OUT.png, OUT.samples.png, OUT.ckpt
kiln render's image, preview, sample heat map and checkpoint
.TP
.I OUT.done
kiln batch's mark of a complete render (the command line that made it)
.TP
.I DIR/manifest.json, DIR/shard.sbatch, DIR/merge.sbatch, DIR/logs/
a farm job directory (kiln farm submit \-d DIR)
[SEE ALSO]
docs/output.md (the EXR and the JSON schema), docs/farm.md, docs/long\-renders.md in the kiln sources.
SECTIONS
