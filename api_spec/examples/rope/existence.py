# Is there any gray hollow pulley in the video?
# expected: yes

def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    gray_hollow_pulleys = rope_scene.find("gray hollow pulley")
    return bool_to_yesno(len(gray_hollow_pulleys) > 0)
