# Is the left cloth much harder to bend or have wrinkles than the other?
# expected: yes

def execute_command(video):
    cloth_scene = SoftScene(video, 'cloth')
    left_cloth = cloth_scene.find("left cloth")
    right_cloth = cloth_scene.find("right cloth")

    # Bending is how easily a cloth bends: the cloth harder to bend has the smaller value.
    left_bending, right_bending = cloth_scene.query_pair('bending', left_cloth, right_cloth)

    return bool_to_yesno(left_bending < right_bending)
