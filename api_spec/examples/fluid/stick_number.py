# How many sticks are there in the video?
# expected: 3

def execute_command(video):
    fluid_scene = SoftScene(video, 'fluid')
    # The sticks of a container's funnel are part of the container, not sticks.
    sticks = fluid_scene.find("stick")
    return len(sticks)
