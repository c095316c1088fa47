# How many purple objects are there in the video?
# expected: 3

def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    purple_objects = rope_scene.find("purple")
    return len(purple_objects)
