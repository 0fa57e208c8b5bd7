-- Prints where saccaded sees each instance: lua5.2 print_instances.lua [URL] [FRAMES]
local lcm = require('lcm')
local saccade = require('saccade')

local lc = lcm.lcm.new(arg[1] or 'udpm://239.255.76.67:7667?ttl=0')
local frames = tonumber(arg[2] or '0')  -- 0: until Ctrl-C
local seen = 0
lc:subscribe('SACCADE_DETECTIONS', function(channel, data)
  local d = saccade.detections_t.decode(data)
  for _, i in ipairs(d.instances) do  -- centroid: where the object is
    print(string.format('%s at (%.3f, %.3f, %.3f) m in %s, confidence %.2f', i.model_name,
                        i.centroid[1], i.centroid[2], i.centroid[3], d.frame, i.confidence))
  end
  io.stdout:flush()
  if d.num_instances > 0 then seen = seen + 1 end
end)
while frames == 0 or seen < frames do lc:handle() end
