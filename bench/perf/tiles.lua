-- tiles.lua — wrk script for `make bench` (bench/perf/stored.py): each connection GETs the
-- 256² tiles (TOCHER_TILE_FORMAT, default png) of one zoom level of a stored mesh in turn (TOCHER_TILE_BASE = /v1/meshes/ID/tiles,
-- TOCHER_TILE_Z) for wrk's duration; the run is printed as one "WRKJSON {...}" line.
local base = os.getenv("TOCHER_TILE_BASE")
local z = tonumber(os.getenv("TOCHER_TILE_Z"))
local fmt = os.getenv("TOCHER_TILE_FORMAT") or "png"
local side = 2 ^ z
local threads = {}

function setup(thread)
  thread:set("id", #threads)
  table.insert(threads, thread)
end

function init(args)
  k = id * 7   -- each connection starts at another tile
end

function request()
  local x, y = k % side, math.floor(k / side) % side
  k = k + 1
  return wrk.format("GET", string.format("%s/%d/%d/%d.%s", base, z, x, y, fmt))
end

done = function(summary, latency, requests)
  io.write(string.format("WRKJSON {\"requests\": %d, \"duration_us\": %d, \"errors\": %d, \"non2xx\": %d, \"p50_us\": %d, \"p90_us\": %d, \"p99_us\": %d, \"max_us\": %d}\n",
    summary.requests, summary.duration, summary.errors.connect + summary.errors.read + summary.errors.write + summary.errors.timeout,
    summary.errors.status, latency:percentile(50), latency:percentile(90), latency:percentile(99), latency.max))
end
