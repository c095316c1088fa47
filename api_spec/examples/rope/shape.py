# How many solid pulleys are there in the video?
# expected: 3

def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    solid_pulleys = rope_scene.find("solid pulley")
    return len(solid_pulleys)
