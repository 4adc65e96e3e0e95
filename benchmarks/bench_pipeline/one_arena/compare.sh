#!/bin/bash
cd "$(dirname "$0")/../.."; source devel/setup.bash
# The manager's malloc tunables before (OLD) and after (NEW, now the launch files' default), one run
# after the other: one person (3 x 1500 frames) and a five-person crowd scene (2 x 2700 frames) at 30 Hz.
# Prints one line a run: frames reaching states, frames over 50 ms, max, median and p95 latency, cores.
OLD="glibc.malloc.mmap_threshold=536870912:glibc.malloc.trim_threshold=1073741824"
NEW="glibc.malloc.mmap_threshold=536870912:glibc.malloc.trim_threshold=1073741824:glibc.malloc.arena_max=1:glibc.malloc.hugetlb=1"
mkdir -p "${OUT:-build/bench_pipeline/one_arena}"
summ() { python3 - "$1" <<'P'
import csv,sys,json
out=sys.argv[1]
r=list(csv.DictReader(open(out+'/frames.csv')))
lat=sorted(float(x['latency_ms']) for x in r if x['latency_ms'])
s=json.load(open(out+'/summary.json'))
print(out.split('/')[-1], "reached", len(lat), "of", len(r), "over50ms", sum(l>50 for l in lat), "max %.0f"%lat[-1], "median %.1f p95 %.1f"%(lat[len(lat)//2], lat[int(.95*len(lat))]), "cores", s.get('cores', s.get('cpu_cores')), flush=True)
P
}
for i in 1 2 3; do
  for v in old new; do T=$OLD; [ $v = new ] && T=$NEW
    o=${OUT:-build/bench_pipeline/one_arena}/p1_${v}_$i; scripts/bench_pipeline --mode rate --rate 30 --frames 1500 --no-build --output $o --malloc-tunables "$T" > $o.log 2>&1; summ $o
  done
done
for i in 1 2; do
  for v in old new; do T=$OLD; [ $v = new ] && T=$NEW
    o=${OUT:-build/bench_pipeline/one_arena}/p5_${v}_$i; scripts/bench_pipeline --mode rate --rate 30 --frames 2700 --no-build --bags ${CROWD_BAG:?a five-person raw-image bag: synth --dataset crowd --people 5 --scenes 1 --seconds 30 --raw-images} --output $o --malloc-tunables "$T" > $o.log 2>&1; summ $o
  done
done
